"""roar_py_remote without ROS: ROAR_PY's wire format (pyserde's MessagePack, pinned byte for byte), the
spaces it ships as pickles (and the pickles it refuses), and a server and client over loopback websockets
streaming a world of this file's own (its car driven, its camera received, clients kept apart). The same
over roar_sim, as two processes, is test_roar_py_programs."""
import asyncio
import base64
import io
import os
import pickle
import socket
import subprocess
import sys
import zlib

import msgpack
import numpy as np
import pytest
from PIL import Image

import roar_py_interface as rpi
import roar_py_remote
from roar_py_interface import spaces
from roar_py_remote import wire

Scheme = rpi.RoarPyRemoteSupportedSensorSerializationScheme


# ---- the wire format ---------------------------------------------------------------------------------------

def test_a_request_is_pyserdes_msgpack_byte_for_byte():
    # pyserde's to_msgpack: a dataclass as a map of its fields in order, int keys kept, arrays as lists.
    request = roar_py_remote.RoarPyRemoteWorldObsInfoRequest(
        need_init_info=True, step=True,
        actor_request_map={0: roar_py_remote.RoarPyRemoteActorObsInfoRequest(
            close=False, sensors_request={3: roar_py_remote.RoarPyRemoteSensorObsInfoRequest(False, True)},
            need_action_space_spec=False, action=np.array([0.0, 0.0, 0.0, 0.2, 0.4], dtype=np.float32))},
        sensor_request_map={})
    expected = msgpack.packb({
        "need_init_info": True, "step": True,
        "actor_request_map": {0: {"close": False, "sensors_request": {3: {"close": False, "need_obs_spec": True}},
                                  "need_action_space_spec": False,
                                  "action": np.array([0.0, 0.0, 0.0, 0.2, 0.4], dtype=np.float32).tolist()}},
        "sensor_request_map": {}}, use_bin_type=True)
    assert wire.to_msgpack(request) == expected
    back = wire.from_msgpack(roar_py_remote.RoarPyRemoteWorldObsInfoRequest, expected)
    assert back.actor_request_map[0].sensors_request[3].need_obs_spec is True
    assert back.actor_request_map[0].action == pytest.approx([0.0, 0.0, 0.0, 0.2, 0.4])


def jpeg_base64(rgb: np.ndarray) -> str:
    buffer = io.BytesIO()
    Image.fromarray(rgb, mode="RGB").save(buffer, format="JPEG")
    return base64.b64encode(buffer.getvalue()).decode("ascii")


def packed(space) -> str:
    return base64.b64encode(zlib.compress(pickle.dumps(space))).decode("ascii")


def server_message(stepped=True, init=True):
    """A world message as ROAR_PY's server writes it, built by hand from its dataclasses' fields."""
    waypoint = {"location": [1.0, 2.0, 0.0], "roll_pitch_yaw": [0.0, 0.0, 0.5], "lane_width": 12.0}
    camera = {"name": "carla_camera", "control_timestep": 0.0,
              "last_data": jpeg_base64(np.full((40, 60, 3), 200, np.uint8)),
              "last_data_type": "RoarPyCameraSensorDataRGB",
              "obs_spec": packed(rpi.RoarPyCameraSensorDataRGB.gym_observation_space(60, 40)), "is_closed": False}
    actor = {"name": "roar_py_remote_vehicle", "control_timestep": 0.05, "sensors_map": {0: camera},
             "is_closed": False, "action_spec": packed(rpi.vehicle_action_spec())}
    return msgpack.packb({
        "init_info": {"maneuverable_waypoints": [waypoint], "comprehensive_waypoints": {7: [waypoint]},
                      "is_asynchronous": False} if init else None,
        "stepped": stepped, "stepped_dt": 0.05, "actor_info_map": {0: actor}, "sensor_info_map": {},
        "last_step_t": 12.5}, use_bin_type=True)


def test_a_world_message_as_roar_pys_server_writes_it_is_read():
    world = roar_py_remote.RoarPyRemoteClientWorld(
        wire.from_msgpack(roar_py_remote.RoarPyRemoteWorldObsInfo, server_message()))
    assert world.maneuverable_waypoints[0] == rpi.RoarPyWaypoint(np.array([1.0, 2.0, 0.0]), np.array([0, 0, 0.5]), 12.0)
    assert list(world.comprehensive_waypoints) == [7]
    vehicle = world.get_actors()[0]
    assert vehicle.name == "roar_py_remote_vehicle" and vehicle.control_timestep == 0.05
    assert list(vehicle.get_action_spec().spaces) == ["brake", "hand_brake", "reverse", "steer", "throttle"]
    camera = vehicle.get_sensors()[0]
    image = asyncio.run(camera.receive_observation())
    assert isinstance(image, rpi.RoarPyCameraSensorDataRGB) and image.get_size() == (60, 40)
    assert abs(int(image.image_rgb.mean()) - 200) <= 2, "JPEG of a grey frame"
    assert camera.get_gym_observation_spec().shape == (40, 60, 3)


def test_a_message_that_does_not_fit_names_the_field():
    bad = msgpack.packb({"need_init_info": False, "step": True,
                         "actor_request_map": {0: {"close": False, "sensors_request": {},
                                                   "need_action_space_spec": False, "action": ["full", "throttle"]}},
                         "sensor_request_map": {}}, use_bin_type=True)
    with pytest.raises(wire.WireFormatError, match=r"RoarPyRemoteWorldObsInfoRequest\.actor_request_map\[0\]\.action"):
        wire.from_msgpack(roar_py_remote.RoarPyRemoteWorldObsInfoRequest, bad)
    with pytest.raises(wire.WireFormatError, match="no field 'step'"):
        wire.from_msgpack(roar_py_remote.RoarPyRemoteWorldObsInfoRequest,
                          msgpack.packb({"need_init_info": False}, use_bin_type=True))
    with pytest.raises(wire.WireFormatError, match="not MessagePack"):
        wire.from_msgpack(roar_py_remote.RoarPyRemoteWorldObsInfoRequest, b"\xc1")


class RunsCode:
    def __reduce__(self):
        return (os.system, ("touch /tmp/roar_py_remote_was_here",))


def test_a_pickle_that_is_no_space_is_refused():
    with pytest.raises(wire.WireFormatError, match="not posix.system|not os.system"):
        wire.unpack_space(packed(RunsCode()))
    assert not os.path.exists("/tmp/roar_py_remote_was_here")
    with pytest.raises(wire.WireFormatError, match="holds a dict, not a space"):
        wire.unpack_space(packed({"a": 1}))
    bomb = base64.b64encode(zlib.compress(b"\0" * (wire.MAX_SPACE_BYTES + 1))).decode("ascii")
    with pytest.raises(wire.WireFormatError, match="more than 16 MiB"):
        wire.unpack_space(bomb)


def test_spaces_cross_as_gymnasiums_pickles():
    for space in (rpi.vehicle_action_spec(auto_gear=False), spaces.Box(-np.inf, np.inf, (3,)),
                  spaces.Tuple([spaces.Discrete(4, start=2), spaces.MultiBinary(2)])):
        space.sample()  # a sampled space pickles its generator too
        assert wire.unpack_space(wire.pack_space(space)) == space


def test_readings_cross_as_roar_py_sends_them():
    location = rpi.RoarPyLocationInWorldSensorData(np.float64(1.5), 2.0, -3.0)
    sensor = _FakeSensor("location", location)
    info = roar_py_remote.RoarPyRemoteSensorObsInfo.from_sensor(sensor, pack_obs_spec=False)
    assert info.last_data_type == "RoarPyLocationInWorldSensorData" and info.obs_spec is None
    assert msgpack.unpackb(zlib.decompress(base64.b64decode(info.last_data))) == {"x": 1.5, "y": 2.0, "z": -3.0}
    assert info.get_last_obs() == location
    collision = rpi.RoarPyCollisionSensorData(object(), object(), np.array([1.0, 0.0, 0.0]))
    wrapped = roar_py_remote.RoarPyRemoteServerSensorWrapper(_FakeSensor("collision", collision))
    sent = wrapped._pack_info().get_last_obs()
    assert sent.actor is None and sent.other_actor is None and sent.impulse_normal.tolist() == [1.0, 0.0, 0.0], \
        "actors stay on the server, as ROAR_PY's shared sensor masks them"


class _FakeSensor(rpi.RoarPySensor):
    def __init__(self, name, reading):
        super().__init__(name, 0.0)
        self.reading, self._closed = reading, False

    def get_gym_observation_spec(self):
        return spaces.Box(-np.inf, np.inf, (3,))

    async def receive_observation(self):
        return self.reading

    def get_last_observation(self):
        return self.reading

    def close(self):
        self._closed = True

    def is_closed(self):
        return self._closed


# ---- a world of this file streamed over loopback ---------------------------------------------------------

class ToyCamera(rpi.RoarPyCameraSensor):
    """Frames whose brightness counts the car's steps."""

    def __init__(self, car):
        super().__init__("carla_camera", 0.0, rpi.RoarPyCameraSensorDataRGB)
        self.car, self.last, self._closed = car, None, False

    @property
    def image_size_width(self):
        return 64

    @property
    def image_size_height(self):
        return 48

    async def receive_observation(self):
        self.last = rpi.RoarPyCameraSensorDataRGB(np.full((48, 64, 3), min(10 * self.car.world.steps, 250), np.uint8))
        return self.last

    def get_last_observation(self):
        return self.last

    def close(self):
        self._closed = True

    def is_closed(self):
        return self._closed or self.car.is_closed()


class ToyCar(rpi.RoarPyBaseVehicle):
    def __init__(self, world, name):
        super().__init__(name, 0.05)
        self.world, self.actions, self._closed, self._sensors = world, [], False, []

    def get_sensors(self):
        return [s for s in self._sensors if not s.is_closed()]

    @rpi.roar_py_append_item
    def attach_camera_sensor(self):
        self._sensors.append(ToyCamera(self))
        return self._sensors[-1]

    async def _apply_action(self, action):
        self.actions.append(action)
        return True

    def close(self):
        self._closed = True

    def is_closed(self):
        return self._closed


class ToyWorld(rpi.RoarPyWorld):
    def __init__(self):
        self.steps, self.t, self.cars = 0, 0.0, []

    @property
    def is_asynchronous(self):
        return False

    def get_actors(self):
        return [c for c in self.cars if not c.is_closed()]

    def get_sensors(self):
        return []

    @property
    def maneuverable_waypoints(self):
        return [rpi.RoarPyWaypoint(np.array([float(i), 0.0, 0.0]), np.zeros(3), 10.0) for i in range(5)]

    @property
    def last_tick_elapsed_seconds(self):
        return self.t

    @rpi.roar_py_append_item
    @rpi.roar_py_thread_sync
    def spawn_vehicle(self, name):
        self.cars.append(ToyCar(self, name))
        return self.cars[-1]

    async def step(self):
        self.steps, self.t = self.steps + 1, self.t + 0.05
        return 0.05


class ToyServer(roar_py_remote.RoarPyWebsocketServerService):
    async def initialize_streamed_world(self, client, world):
        vehicle = world.spawn_vehicle(f"car_{len(world.get_actors())}")
        vehicle.attach_camera_sensor()
        await world.step()
        return True


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


async def with_server(world, body, **manager_options):
    port = free_port()
    manager = roar_py_remote.RoarPyRemoteServerWorldManager(world, False, **manager_options)
    server = asyncio.ensure_future(ToyServer(manager).run_server(bind_port=port))
    for _ in range(200):
        try:
            socket.create_connection(("127.0.0.1", port), timeout=1).close()
            break
        except OSError:
            await asyncio.sleep(0.01)
    try:
        return await body(f"ws://127.0.0.1:{port}")
    finally:
        server.cancel()
        await asyncio.gather(server, return_exceptions=True)


GO = {"throttle": 0.4, "steer": 0.2, "brake": 0.0, "hand_brake": np.array([0]), "reverse": np.array([0]),
      "target_gear": 3}


def test_a_client_drives_its_car_and_sees_its_camera_in_lockstep():
    world = ToyWorld()

    async def drive(uri):
        client_world = await roar_py_remote.RoarPyWebsocketClientService.connect_to_server(uri)
        vehicle = client_world.get_actors()[0]
        camera = vehicle.get_sensors()[0]
        brightness, dts = [], []
        for _ in range(5):
            dts.append(await client_world.step())
            brightness.append(int((await camera.receive_observation()).image_rgb.mean()))
            await vehicle.apply_action(GO)
        steps_seen = world.steps
        await client_world.close()
        return client_world, brightness, dts, steps_seen

    client_world, brightness, dts, steps_seen = asyncio.run(with_server(world, drive))
    car = world.cars[0]
    assert steps_seen == 5, "a synchronous server steps once per client step"
    assert dts == pytest.approx([0.05] * 5) and client_world.last_tick_elapsed_seconds == pytest.approx(0.25)
    assert brightness == sorted(brightness) and brightness[-1] >= 40, "a new frame each step"
    assert len(car.actions) == 4, "each action reaches the car on the server's next tick"
    assert float(car.actions[0]["throttle"]) == pytest.approx(0.4) and float(car.actions[0]["steer"]) == pytest.approx(0.2)
    assert "target_gear" not in car.actions[0], "fields outside the action space stay behind, as in ROAR_PY"
    assert [w.location[0] for w in client_world.maneuverable_waypoints] == [0, 1, 2, 3, 4]
    assert car.is_closed(), "the car of a client that left is closed"


def test_a_client_that_sends_garbage_is_dropped_and_the_others_go_on():
    import websockets

    world = ToyWorld()

    async def two_clients(uri):
        good = await roar_py_remote.RoarPyWebsocketClientService.connect_to_server(uri)
        async with websockets.connect(uri, max_size=None) as bad:
            await bad.recv()
            await bad.send(b"not msgpack at all \xc1")
            with pytest.raises(websockets.exceptions.ConnectionClosed):
                for _ in range(100):
                    await asyncio.wait_for(bad.recv(), 5)
        dts = [await good.step() for _ in range(3)]
        # The first step carries the time the server stepped while this client kept it waiting.
        assert dts[0] >= 0.05 and dts[1:] == pytest.approx([0.05, 0.05])
        return good, [c.is_closed() for c in world.cars]

    good, closed = asyncio.run(with_server(world, two_clients, sync_wait_time_max=0.5))
    assert closed == [False, True], "the bad client's car went with it"
    assert len(good.get_actors()) == 1, "a client sees its own car only"


def test_a_stalled_client_slows_a_synchronous_server_but_never_stops_it():
    world = ToyWorld()

    async def one_stalls(uri):
        await roar_py_remote.RoarPyWebsocketClientService.connect_to_server(uri)  # never steps
        steady = await roar_py_remote.RoarPyWebsocketClientService.connect_to_server(uri)
        return [await steady.step() for _ in range(3)]

    dts = asyncio.run(with_server(world, one_stalls, sync_wait_time_max=0.2))
    assert len(dts) == 3 and all(dt > 0 for dt in dts)


def listening_addresses(port: int):
    """The IPv4 addresses a socket of this machine listens on at port (from /proc/net/tcp)."""
    addresses = []
    with open("/proc/net/tcp") as table:
        for line in list(table)[1:]:
            local, state = line.split()[1], line.split()[3]
            address, local_port = local.split(":")
            if state == "0A" and int(local_port, 16) == port:
                addresses.append(socket.inet_ntoa(int(address, 16).to_bytes(4, "little")))
    return addresses


LISTEN_CHECK = """
import asyncio, sys
sys.path.insert(0, sys.argv[1])
import roar_py_remote, test_roar_py_remote as t
async def bound(where):
    port = t.free_port()
    manager = roar_py_remote.RoarPyRemoteServerWorldManager(t.ToyWorld(), False)
    server = asyncio.ensure_future(t.ToyServer(manager).run_server(bind_port=port, **where))
    await asyncio.sleep(0.3)
    print(t.listening_addresses(port))
    server.cancel()
    await asyncio.gather(server, return_exceptions=True)
asyncio.run(bound(eval(sys.argv[2])))
"""


def test_the_server_listens_on_loopback_unless_told():
    # Without scripts/ros_env.sh's preloaded shim, which keeps every socket of the tests on loopback.
    env = {k: v for k, v in os.environ.items() if k != "LD_PRELOAD"}

    def bound(where: str):
        out = subprocess.run([sys.executable, "-c", LISTEN_CHECK, os.path.dirname(__file__), where], env=env,
                             capture_output=True, text=True, timeout=60)
        assert out.returncode == 0, out.stderr
        return out.stdout.strip()

    assert bound("{}") == "['127.0.0.1']"
    assert bound("{'bind_addr': ''}") == "['0.0.0.0']", "every interface when asked, as ROAR_PY's default"
