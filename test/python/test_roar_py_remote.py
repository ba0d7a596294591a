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
from roar_py_interface import space_pickle
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
    with pytest.raises(wire.WireFormatError, match=r"not MessagePack \(a byte that starts no MessagePack value\)"):
        wire.from_msgpack(roar_py_remote.RoarPyRemoteWorldObsInfoRequest, b"\xc1")
    with pytest.raises(wire.WireFormatError, match=r"not MessagePack \(nested deeper than the decoder allows\)"):
        wire.from_msgpack(roar_py_remote.RoarPyRemoteWorldObsInfoRequest, b"\x91" * 5000 + b"\xc0")
    with pytest.raises(wire.WireFormatError, match=r"not MessagePack \(Unpack failed: incomplete input\)"):
        wire.from_msgpack(roar_py_remote.RoarPyRemoteWorldObsInfoRequest, b"\x92\x01")


class RunsCode:
    def __reduce__(self):
        return (os.system, ("touch /tmp/roar_py_remote_was_here",))


def test_a_pickle_that_is_no_space_is_refused():
    with pytest.raises(wire.WireFormatError, match="not posix.system|not os.system"):
        wire.unpack_space(packed(RunsCode()))
    assert not os.path.exists("/tmp/roar_py_remote_was_here")
    with pytest.raises(wire.WireFormatError, match="holds a dict, not a space"):
        wire.unpack_space(packed({"a": 1}))
    bomb = base64.b64encode(zlib.compress(b"\0" * (space_pickle.MAX_PICKLE_BYTES + 1))).decode("ascii")
    with pytest.raises(wire.WireFormatError, match=f"more than {space_pickle.MAX_PICKLE_BYTES >> 20} MiB"):
        wire.unpack_space(bomb)


def test_spaces_cross_as_gymnasiums_pickles():
    for space in (rpi.vehicle_action_spec(auto_gear=False), spaces.Box(-np.inf, np.inf, (3,)),
                  spaces.Tuple([spaces.Discrete(4, start=2), spaces.MultiBinary(2)])):
        space.sample()  # a sampled space pickles its generator too
        assert wire.unpack_space(wire.pack_space(space)) == space
    for width, height in ((800, 600), (1920, 1080), (3840, 2160)):  # ROAR_PY's default camera to CARLA's 4K
        camera = spaces.Box(0, 255, (height, width, 3), dtype=np.uint8)
        assert wire.unpack_space(wire.pack_space(camera)) == camera


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
        assert camera.sensordata_type is rpi.RoarPyCameraSensorDataRGB, "the readings' class, as ROAR_PY's"
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


ACROSS_THE_NETWORK = """
import asyncio, os, subprocess, sys
sys.path.insert(0, sys.argv[1])
import websockets
import roar_py_remote, test_roar_py_remote as t
from roar_py_remote import wire
ADDRESS = "10.200.0.1"  # of a veth interface in this network namespace: not loopback
for command in ("ip link set lo up", "ip link add roar0 type veth peer name roar1",
                f"ip addr add {ADDRESS}/24 dev roar0", "ip link set roar0 up", "ip link set roar1 up"):
    subprocess.run(command.split(), check=True)
async def reached(**where):
    port = t.free_port()
    manager = roar_py_remote.RoarPyRemoteServerWorldManager(t.ToyWorld(), False)
    server = asyncio.ensure_future(t.ToyServer(manager).run_server(bind_port=port, **where))
    await asyncio.sleep(0.3)
    try:
        async with websockets.connect(f"ws://{ADDRESS}:{port}", open_timeout=10) as client:
            await client.send(wire.to_msgpack(roar_py_remote.RoarPyRemoteWorldObsInfoRequest(
                need_init_info=True, step=True, actor_request_map={}, sensor_request_map={})))
            return len(await asyncio.wait_for(client.recv(), 10)) > 0
    except OSError:
        return False
    finally:
        server.cancel()
        await asyncio.gather(server, return_exceptions=True)
os.environ.pop("ROAR_PY_REMOTE_BIND", None)
print("unasked", asyncio.run(reached()))
print("asked", asyncio.run(reached(bind_addr="")))
os.environ["ROAR_PY_REMOTE_BIND"] = "0.0.0.0"
print("by the environment", asyncio.run(reached()))
"""


def test_other_machines_reach_the_server_only_when_asked():
    """In a network namespace of its own, a client at a non-loopback address of the server's machine reaches a
    server whose program passed no address only when ROAR_PY_REMOTE_BIND says so, or when the program asks
    for every interface (ROAR_PY's run_server(bind_addr=""))."""
    env = {k: v for k, v in os.environ.items() if k != "LD_PRELOAD"}  # the tests' loopback shim
    out = subprocess.run(["unshare", "--net", sys.executable, "-c", ACROSS_THE_NETWORK, os.path.dirname(__file__)],
                         env=env, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr[-3000:]
    assert out.stdout.split("\n")[:3] == ["unasked False", "asked True", "by the environment True"], out.stdout
    assert "clients on other machines cannot connect (ROAR_PY_REMOTE_BIND=0.0.0.0" in out.stderr, out.stderr
    assert "anyone who reaches it can drive a car here" in out.stderr, out.stderr


# ---- a hostile server ----------------------------------------------------------------------------------------

HOSTILE_SERVER = r'''
import asyncio, sys, websockets
first, later = open(sys.argv[2], "rb").read(), open(sys.argv[3], "rb").read()

async def serve(websocket):
    await websocket.send(first)
    async for _ in websocket:
        await websocket.send(later)

async def main():
    async with websockets.serve(serve, "127.0.0.1", int(sys.argv[1]), max_size=None):
        await asyncio.Future()

asyncio.run(main())
'''


class ZeroSizeHugeArray:
    """Pickles as NumPy's array of 100 million zero-byte values: nothing to send, gigabytes once used."""

    def __reduce__(self):
        return (np.core.multiarray._reconstruct, (np.ndarray, (0,), b"b"),
                (1, (100_000_000,), np.dtype("V0"), False, b""))


def sensor_message(reading_type, reading, obs_spec=None, stepped=True):
    """A world message with one sensor on one car, its reading (base64) and observation space as given."""
    sensor = {"name": "hostile", "control_timestep": 0.0, "last_data": reading, "last_data_type": reading_type,
              "obs_spec": obs_spec, "is_closed": False}
    actor = {"name": "car", "control_timestep": 0.05, "sensors_map": {0: sensor}, "is_closed": False,
             "action_spec": packed(rpi.vehicle_action_spec())}
    return msgpack.packb({"init_info": {"maneuverable_waypoints": None, "comprehensive_waypoints": None,
                                        "is_asynchronous": False} if not stepped else None,
                          "stepped": stepped, "stepped_dt": 0.05, "actor_info_map": {0: actor}, "sensor_info_map": {},
                          "last_step_t": 1.0}, use_bin_type=True)


def jpeg_of_size(width, height) -> bytes:
    """A JPEG whose header says width x height: a small real one with its frame header patched."""
    buffer = io.BytesIO()
    Image.new("RGB", (16, 16)).save(buffer, format="JPEG")
    data = bytearray(buffer.getvalue())
    sof = data.index(b"\xff\xc0")
    data[sof + 5:sof + 9] = height.to_bytes(2, "big") + width.to_bytes(2, "big")
    return bytes(data)


def hostile_attacks():
    """Each attack: the server's first message, what it sends after each request, what the refusal names."""
    b64 = lambda data: base64.b64encode(data).decode("ascii")  # noqa: E731
    runs = msgpack.packb({"flattened": [0.0], "space": zlib.compress(pickle.dumps(RunsCode()))}, use_bin_type=True)
    huge_box = spaces.Box(0.0, 1.0, (2,))
    huge_box.__dict__["_shape"] = (100_000_000,)
    bomb = zlib.compress(b"\0" * (200 << 20), 9)  # 200 MiB from 200 kB
    quiet = sensor_message("RoarPyLocationInWorldSensorData", None, stepped=False)

    def reading(kind, data):
        return quiet, sensor_message(kind, b64(data))

    def space(packed_space):
        first = sensor_message("RoarPyLocationInWorldSensorData", None, packed_space, stepped=False)
        return first, first
    return {
        "a custom lambda reading that runs code": (*reading("RoarPyCustomLambdaSensorData", runs),
                                                   "RoarPyCustomLambdaSensorData.space"),
        "an observation space of 100 million values": (*space(packed(huge_box)), "obs_spec: the space"),
        "an array of 100 million zero-byte values": (*space(packed(ZeroSizeHugeArray())), "dtype of item size 0"),
        "a zlib bomb as a reading": (*reading("RoarPyLocationInWorldSensorData", bomb), "inflates to more than"),
        "a JPEG of 12000 x 7400": (*reading("RoarPyCameraSensorDataRGB", jpeg_of_size(12000, 7400)),
                                   "12000x7400 is more than"),
        "a JPEG of 196 megapixels": (*reading("RoarPyCameraSensorDataRGB", jpeg_of_size(14000, 14000)),
                                     f"more than {rpi.sensors.MAX_IMAGE_PIXELS} pixels"),
    }


@pytest.mark.parametrize("attack", list(hostile_attacks()))
def test_a_hostile_server_cannot_run_code_or_exhaust_a_client(tmp_path, attack):
    """A server process sends what a hostile server would: the client refuses it with one ConnectionError naming
    what was sent, runs no code and allocates nothing by it (its peak memory grows by less than 200 MB)."""
    import resource
    import time

    first, later, named = hostile_attacks()[attack]
    (tmp_path / "first").write_bytes(first)
    (tmp_path / "later").write_bytes(later)
    (tmp_path / "server.py").write_text(HOSTILE_SERVER)
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    server = subprocess.Popen([sys.executable, str(tmp_path / "server.py"), str(port), str(tmp_path / "first"),
                               str(tmp_path / "later")])
    if os.path.exists("/tmp/roar_py_remote_was_here"):
        os.remove("/tmp/roar_py_remote_was_here")
    try:
        deadline = time.time() + 60
        while True:  # the server starting (slowly on a loaded machine)
            try:
                socket.create_connection(("127.0.0.1", port), timeout=1).close()
                break
            except OSError:
                assert time.time() < deadline and server.poll() is None, "the hostile server did not start"
                time.sleep(0.05)
        peak_before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss

        async def connect_and_step():
            world = await roar_py_remote.RoarPyWebsocketClientService.connect_to_server(f"ws://127.0.0.1:{port}")
            await world.step()
            await world.get_actors()[0].get_sensors()[0].receive_observation()

        with pytest.raises(ConnectionError) as refused:
            asyncio.run(connect_and_step())
    finally:
        server.kill()
        server.wait()
    assert named in str(refused.value), refused.value
    assert not os.path.exists("/tmp/roar_py_remote_was_here"), "the server ran code in the client"
    grown_mb = (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - peak_before) / 1024
    assert grown_mb < 200, f"the client's peak memory grew by {grown_mb:.0f} MB"


def test_a_huge_finite_action_is_clamped_not_the_end_of_the_session():
    """A throttle of 1e39 is finite as sent but not in float32: it reaches the car clamped to the action space's
    range, as CARLA clamps a control, and the client's session goes on."""
    world = ToyWorld()
    car = world.spawn_vehicle("car")
    wrapper = roar_py_remote.RoarPyRemoteServerActorWrapper(car)
    spec = car.get_action_spec()
    flat = np.full(spaces.flatdim(spec), 1e39)
    request = roar_py_remote.RoarPyRemoteActorObsInfoRequest(close=False, sensors_request={},
                                                             need_action_space_spec=False, action=flat)
    assert wrapper._depack_info(request)
    asyncio.run(wrapper.receive_observation())
    action = car.actions[-1]
    assert all(np.all(np.isfinite(np.asarray(v, dtype=np.float64))) for v in action.values()), action
    assert spec.contains(action), action
    assert not car.is_closed()


def test_a_client_that_never_reads_or_floods_is_dropped_and_the_others_go_on():
    """A client that sends its requests and never reads its answers, and one that floods requests, hold up no
    one: each is dropped (its car closed), and a steady client steps on."""
    import websockets

    world = ToyWorld()
    request = wire.to_msgpack(roar_py_remote.RoarPyRemoteWorldObsInfoRequest(
        need_init_info=True, step=True, actor_request_map={}, sensor_request_map={}))

    async def bad_and_good(uri):
        never_reads = await websockets.connect(uri, max_size=None, max_queue=1)
        floods = await websockets.connect(uri, max_size=None)

        async def send_and_never_read():
            try:
                while True:
                    await never_reads.send(request)
                    await asyncio.sleep(0.02)
            except websockets.exceptions.ConnectionClosed:
                pass

        rude = asyncio.ensure_future(send_and_never_read())
        await asyncio.gather(*(floods.send(request) for _ in range(1000)), return_exceptions=True)
        steady = await roar_py_remote.RoarPyWebsocketClientService.connect_to_server(uri)
        dts = []
        # Until the server has dropped the one that never reads (its answers unread, then its pings): a
        # keepalive's 15 s; given up after 40 s.
        give_up = asyncio.get_running_loop().time() + 40.0
        while not world.cars[0].is_closed() and asyncio.get_running_loop().time() < give_up:
            dts.append(await asyncio.wait_for(steady.step(), 60))
            await asyncio.sleep(0.01)
        rude.cancel()
        closed = [c.is_closed() for c in world.cars]
        await steady.close()
        return dts, closed

    dts, closed = asyncio.run(with_server(world, bad_and_good, sync_wait_time_max=0.5))
    assert len(dts) >= 20 and all(dt > 0 for dt in dts), "the steady client stepped on meanwhile"
    assert closed[:2] == [True, True], "the client that never reads and the flooding one were dropped"
    assert closed[2] is False


def test_a_shared_sensor_wrapper_is_a_read_only_sensor_wrapper():
    class Collisions(rpi.RoarPyCollisionSensor):
        def __init__(self):
            super().__init__("collision", 0.05)
            self.reading = rpi.RoarPyCollisionSensorData(actor="mine", other_actor="theirs",
                                                        impulse_normal=np.array([1.0, 2.0, 3.0]))

        def get_last_observation(self):
            return self.reading

        def is_closed(self):
            return False

    shared = roar_py_remote.RoarPyRemoteSharedSensorWrapper(Collisions())
    assert isinstance(shared, rpi.RoarPySensorWrapper) and shared.name == "collision"
    seen = shared.get_last_observation()
    assert seen.actor is None and seen.other_actor is None and list(seen.impulse_normal) == [1.0, 2.0, 3.0]
    with pytest.raises(PermissionError):
        asyncio.run(shared.receive_observation())
    with pytest.raises(PermissionError):
        shared.name = "renamed"
