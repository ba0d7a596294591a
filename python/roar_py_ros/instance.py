"""RoarPyRosInstance: what RoarPyCarlaInstance is to CARLA, over roar_sim."""
import os
import typing

from .connection import PrivateSim, RoarSimError, Services, connect, sim_registered
from .world import RoarPyRosWorld

CLIENT_VERSION = "roar_py_ros 1.0"


class RoarPyRosInstance:
    """Connects to the roar_sim of ROS_MASTER_URI; when none is reachable, starts a private ROS master,
    roar_sim and waypoint_server (launch/roar_py.launch) and stops them on close(). map_name: a map in
    maps/ or a map folder's path, loaded when given."""

    def __init__(self, map_name: typing.Optional[str] = None, timeout: float = 60.0):
        if map_name is not None and (not isinstance(map_name, str) or not map_name):
            raise ValueError(f"RoarPyRosInstance: map_name must be a map's name or folder, got {map_name!r}")
        self._closed = True
        self._private: typing.Optional[PrivateSim] = connect(map_name, timeout)
        self._services = Services()
        self._closed = False
        self.world = RoarPyRosWorld(self)
        if map_name is not None and self._private is None and self.world.map_name != self._map_display(map_name):
            self.load_world(map_name)

    @staticmethod
    def _map_display(map_name: str) -> str:
        return os.path.basename(os.path.normpath(map_name))

    def _check_open(self):
        if self._closed:
            raise RuntimeError("the RoarPyRosInstance is closed")

    def _sim_alive(self) -> bool:
        if self._private is not None:
            return self._private.alive()
        return sim_registered()

    def get_available_maps(self) -> typing.List[str]:
        self._check_open()
        from roar_ros.srv import ListMaps

        return list(self._services.call("/roar_sim/list_maps", ListMaps).maps)

    def load_world(self, map_name: str, reset_settings: bool = True):
        """Loads a map (a name of get_available_maps() or a map folder's path); every car goes."""
        self._load(map_name, reset_settings)

    def reload_world(self, reset_settings: bool = True):
        """Loads the current map afresh from its files; every car goes."""
        self._load("", reset_settings)

    def _load(self, map_name: str, reset_settings: bool):
        self._check_open()
        from roar_ros.srv import LoadMap

        if not isinstance(map_name, str):
            raise ValueError(f"load_world: map_name must be a string, got {map_name!r}")
        world = self.world
        with world._cond:
            waypoints_before, spawns_before = world._waypoints_count, world._spawn_count
        response = self._services.call("/roar_sim/load_map", LoadMap, check=False, map=map_name)
        if not response.success:
            raise ValueError(f"load_world('{map_name}'): {response.message}")
        world._forget_vehicles()
        world._wait(lambda: world._waypoints_count > waypoints_before and world._spawn_count > spawns_before,
                    f"waypoint_server's waypoints of '{response.name}'")
        if reset_settings:
            world._set_stepping(mode="step", control_dt=0.05, physics_dt=0.005)
        world._refresh_settings()

    def get_client_version(self) -> str:
        return CLIENT_VERSION

    def get_server_version(self) -> str:
        self._check_open()
        from roar_ros.srv import GetWorldInfo

        return "roar_sim " + self._services.call("/roar_sim/get_world_info", GetWorldInfo).version

    def clean_actors_not_registered(self, typeid_wildcard: typing.Sequence[str] = ("vehicle.*", "sensor.*")):
        self._check_open()
        self.world.clean_actors_not_registered(typeid_wildcard)

    def close(self):
        """Removes this program's cars from roar_sim, and stops roar_sim if this instance started it."""
        if self._closed:
            return
        try:
            if self._sim_alive():
                for vehicle in self.world.get_actors():
                    vehicle.close()
        except RoarSimError:
            pass
        finally:
            self.world.close()
            self._services.close()
            self._closed = True
            if self._private is not None:
                self._private.stop()

    def is_closed(self) -> bool:
        return self._closed

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        try:
            self.close()
        except Exception:  # noqa: BLE001 - nothing may escape a finaliser
            pass
