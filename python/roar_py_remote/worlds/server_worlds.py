"""ROAR_PY's server worlds: the world each client sees, and the manager that steps the shared one."""
import asyncio
import contextlib
import threading
import time
import typing

import roar_py_interface as rpi

from ..actors.remote_actor_wrappers import _refreshed, RoarPyRemoteServerActorWrapper
from ..base import register_object_with_remote_message, RoarPyObjectWithRemoteMessage
from ..sensors import RoarPyRemoteServerSensorWrapper
from .remote_worlds import _log, RoarPyRemoteWorldInitInfo, RoarPyRemoteWorldObsInfo, RoarPyRemoteWorldObsInfoRequest


class RoarPyRemoteMaskedWorld(rpi.RoarPyWorld):
    """One client's view of the shared world: the public attributes of the world, its own actors and
    sensors (those spawned or attached through this view), and the time since its own last step."""

    def __init__(self, server_world: "RoarPyRemoteServerWorldManager", underlying_world: rpi.RoarPyWorld,
                 shared_lock: threading.RLock):
        super().__init__()
        self._manager = server_world
        self._underlying_world = underlying_world
        self._shared_lock = shared_lock
        self._actors: typing.List[rpi.RoarPyActor] = []
        self._sensors: typing.List[rpi.RoarPySensor] = []
        self._awaiting_request = False  # its client has been answered and owes the next request
        self._next_step_dt = 0.0
        self._last_step_timestamp = underlying_world.last_tick_elapsed_seconds
        self._next_step_timestamp = self._last_step_timestamp
        self._closed = False

    def __getattr__(self, name: str):
        if name.startswith("_"):
            raise AttributeError(f"Cannot access private attribute '{name}' of the shared world")
        value = getattr(self._underlying_world, name)
        if callable(value) and (getattr(value, "is_append_item", False) or getattr(value, "is_remove_item", False)):
            def through_this_view(*args, **kwargs):
                with self._manager._modified_by(self):
                    return value(*args, **kwargs)

            return through_this_view
        return value

    @property
    def is_asynchronous(self) -> bool:
        return self._manager.is_asynchronous

    def get_actors(self) -> typing.List[rpi.RoarPyActor]:
        self._actors = [a for a in self._actors if not a.is_closed()]
        return list(self._actors)

    def get_sensors(self) -> typing.List[rpi.RoarPySensor]:
        self._sensors = [s for s in self._sensors if not s.is_closed()]
        return list(self._sensors)

    @property
    def maneuverable_waypoints(self):
        return self._underlying_world.maneuverable_waypoints

    @property
    def comprehensive_waypoints(self):
        return self._underlying_world.comprehensive_waypoints

    @property
    def last_tick_elapsed_seconds(self) -> float:
        return self._last_step_timestamp

    def _collect_step(self) -> float:
        """The shared world's time since this view's last step, as of its newest step."""
        with self._shared_lock:
            dt, self._next_step_dt = self._next_step_dt, 0.0
            self._last_step_timestamp = self._next_step_timestamp
        return dt

    async def step(self) -> float:
        self._awaiting_request = False
        return self._collect_step()

    def close(self):
        if self._closed:
            return
        self._closed = True
        with self._shared_lock:
            for item in self._actors + self._sensors:
                if not item.is_closed():
                    item.close()
            self._actors.clear()
            self._sensors.clear()
            self._manager._del_masked_world(self)


class RoarPyRemoteServerWorldManager:
    """Shares one world among the clients of a server (see the module's notes on stepping)."""

    def __init__(self, world: rpi.RoarPyWorld, is_asynchronous: bool, sync_wait_time_max: float = 5.0,
                 constructor_to_subworld: typing.Callable[..., RoarPyRemoteMaskedWorld] = RoarPyRemoteMaskedWorld,
                 thread_safe: bool = True):
        if world is None:
            raise ValueError("RoarPyRemoteServerWorldManager: world is None")
        if not sync_wait_time_max >= 0:
            raise ValueError(f"RoarPyRemoteServerWorldManager: sync_wait_time_max must be >= 0 s, got {sync_wait_time_max}")
        self._shared_lock = threading.RLock()
        shared = rpi.RoarPyThreadSafeWrapper(world, self._shared_lock) if thread_safe else world
        self._underlying_world = rpi.RoarPyAddItemWrapper(shared, self._add_item, self._remove_item)
        self._is_asynchronous = bool(is_asynchronous)
        self._masked_worlds: typing.List[RoarPyRemoteMaskedWorld] = []
        self._sync_wait_time_max = float(sync_wait_time_max)
        self._constructor_to_subworld = constructor_to_subworld
        self._last_subworld_modified: typing.Optional[RoarPyRemoteMaskedWorld] = None

    @property
    def is_asynchronous(self) -> bool:
        return self._is_asynchronous

    def get_world(self) -> RoarPyRemoteMaskedWorld:
        with self._shared_lock:
            masked = self._constructor_to_subworld(self, self._underlying_world, self._shared_lock)
            self._masked_worlds.append(masked)
            _log.info("a client's world opened (%d open)", len(self._masked_worlds))
            return masked

    def _del_masked_world(self, world: RoarPyRemoteMaskedWorld):
        with self._shared_lock:
            if world in self._masked_worlds:
                self._masked_worlds.remove(world)
                _log.info("a client's world closed (%d open)", len(self._masked_worlds))
            if self._last_subworld_modified is world:
                self._last_subworld_modified = None

    @contextlib.contextmanager
    def _modified_by(self, world: RoarPyRemoteMaskedWorld):
        """While a view spawns or removes through the shared world: what is added or removed is its."""
        with self._shared_lock:
            self._last_subworld_modified = world
            try:
                yield
            finally:
                self._last_subworld_modified = None

    def _add_item(self, item):
        world = self._last_subworld_modified
        if world is None or item is None:
            return
        unwrapped = item.unwrapped if isinstance(item, rpi.RoarPyWrapper) else item
        if isinstance(unwrapped, rpi.RoarPyActor):
            world._actors.append(item)
        elif isinstance(unwrapped, rpi.RoarPySensor):
            world._sensors.append(item)

    def _remove_item(self, item):
        world = self._last_subworld_modified
        if world is None:
            return
        for items in (world._actors, world._sensors):
            if item in items:
                items.remove(item)

    async def _wait_for_clients(self):
        deadline = time.time() + self._sync_wait_time_max
        while any(w._awaiting_request for w in self._masked_worlds):
            if time.time() >= deadline:
                late = sum(w._awaiting_request for w in self._masked_worlds)
                _log.warning("stepping without %d client(s) that did not ask within %.1f s", late,
                             self._sync_wait_time_max)
                return
            await asyncio.sleep(0.001)

    async def _step(self) -> float:
        """Steps the shared world (a synchronous manager first waits for its clients, and with none
        connected does not step); every client's view collects the time."""
        if not self._is_asynchronous:
            if not self._masked_worlds:
                await asyncio.sleep(0.01)
                return 0.0
            await self._wait_for_clients()
        stepped_dt = await self._underlying_world.step()
        with self._shared_lock:
            for world in self._masked_worlds:
                world._next_step_dt += stepped_dt
                world._next_step_timestamp = self._underlying_world.last_tick_elapsed_seconds
        return stepped_dt


@register_object_with_remote_message(RoarPyRemoteWorldObsInfoRequest, RoarPyRemoteWorldObsInfo)
class RoarPyRemoteServerWorldWrapper(RoarPyObjectWithRemoteMessage[RoarPyRemoteWorldObsInfoRequest,
                                                                   RoarPyRemoteWorldObsInfo], rpi.RoarPyWorldWrapper):
    """A client's masked world on the server: its requests applied, its actors and sensors read and sent."""

    def __init__(self, wrapped_object: RoarPyRemoteMaskedWorld):
        rpi.RoarPyWorldWrapper.__init__(self, wrapped_object, "RoarPyRemoteWorldServerWrapper")
        self.actor_map: typing.Dict[int, RoarPyRemoteServerActorWrapper] = {}
        self.sensor_map: typing.Dict[int, RoarPyRemoteServerSensorWrapper] = {}
        self._last_actor_id = 0
        self._last_sensor_id = 0
        self._stepped = False
        self._stepped_dt = 0.0
        self._req_next_tick = False
        self._req_need_init_info = False

    async def step(self) -> float:
        dt = await self._wrapped_object.step()
        self._stepped, self._stepped_dt = True, dt
        return dt

    def _refresh_actor_list(self) -> None:
        self.actor_map, self._last_actor_id = _refreshed(
            self.actor_map, self._wrapped_object.get_actors(), RoarPyRemoteServerActorWrapper, self._last_actor_id)

    def _refresh_sensor_list(self) -> None:
        self.sensor_map, self._last_sensor_id = _refreshed(
            self.sensor_map, self._wrapped_object.get_sensors(), RoarPyRemoteServerSensorWrapper,
            self._last_sensor_id)

    async def _tick_remote(self) -> None:
        if self._req_next_tick:
            self._req_next_tick = False
            self._stepped, self._stepped_dt = True, self._wrapped_object._collect_step()
        self._refresh_actor_list()
        self._refresh_sensor_list()
        await asyncio.gather(*[a._tick_remote() for a in self.actor_map.values()],
                             *[s._tick_remote() for s in self.sensor_map.values()])

    def _depack_info(self, data: RoarPyRemoteWorldObsInfoRequest) -> bool:
        self._wrapped_object._awaiting_request = False
        self._stepped, self._stepped_dt = False, 0.0
        self._req_need_init_info = data.need_init_info
        self._req_next_tick = data.step
        self._refresh_actor_list()
        for oid, actor_request in data.actor_request_map.items():
            if oid in self.actor_map:
                self.actor_map[oid]._depack_info(actor_request)
        self._refresh_sensor_list()
        for oid, sensor_request in data.sensor_request_map.items():
            if oid in self.sensor_map:
                self.sensor_map[oid]._depack_info(sensor_request)
        return True

    def _init_info(self) -> RoarPyRemoteWorldInitInfo:
        waypoints = self.maneuverable_waypoints
        return RoarPyRemoteWorldInitInfo(maneuverable_waypoints=None if waypoints is None else list(waypoints),
                                         comprehensive_waypoints=self.comprehensive_waypoints,
                                         is_asynchronous=self.is_asynchronous)

    def _pack_info(self) -> RoarPyRemoteWorldObsInfo:
        self._refresh_actor_list()
        self._refresh_sensor_list()
        info = RoarPyRemoteWorldObsInfo(
            init_info=self._init_info() if self._req_need_init_info else None,
            stepped=self._stepped, stepped_dt=self._stepped_dt,
            actor_info_map={oid: actor._pack_info() for oid, actor in self.actor_map.items()},
            sensor_info_map={oid: sensor._pack_info() for oid, sensor in self.sensor_map.items()},
            last_step_t=self.last_tick_elapsed_seconds)
        self._wrapped_object._awaiting_request = True
        return info

    def close(self):
        self._wrapped_object.close()
