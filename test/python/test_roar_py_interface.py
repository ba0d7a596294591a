"""roar_py_interface without ROS: spaces and the gymnasium fallback, waypoints and their tracker, sensors'
data, wrappers, the occupancy-map producer, serialisation, and actions read as ROAR_PY over CARLA reads
them. Each test says the ROAR_PY (or CARLA) behaviour it mirrors."""
import asyncio
import collections
import os
import pickle
import threading
import warnings

import msgpack
import numpy as np
import pytest
import transforms3d
from shapely.geometry import Point, Polygon

import roar_py_interface as rpi
from roar_py_interface import spaces, transforms
from roar_py_ros import conversions

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

Scheme = rpi.RoarPyRemoteSupportedSensorSerializationScheme


# ---- spaces and gymnasium ----------------------------------------------------------------------------------

def test_box_samples_and_contains_like_gymnasium():
    box = spaces.Box(low=0.0, high=1.0, shape=(2,))
    assert box.shape == (2,) and box.dtype == np.float32
    assert box.low.tolist() == [0.0, 0.0] and box.high.tolist() == [1.0, 1.0]
    box.seed(4)
    first = [box.sample() for _ in range(5)]
    box.seed(4)
    assert all(np.array_equal(a, box.sample()) for a in first), "the same seed draws the same samples"
    assert all(box.contains(s) for s in first)
    assert not box.contains(np.array([0.5, 1.5], np.float32))
    assert not box.contains(np.array([0.5], np.float32)), "wrong shape"
    assert not box.contains(np.array([0.5, 0.5], np.float64)), "gymnasium: float64 does not cast safely to float32"
    unbounded = spaces.Box(low=-np.inf, high=np.inf, shape=(3,))
    assert np.all(np.isfinite(unbounded.sample()))
    image = spaces.Box(low=0, high=255, shape=(4, 5, 3), dtype=np.uint8)
    sample = image.sample()
    assert sample.dtype == np.uint8 and image.contains(sample)


def test_discrete_multibinary_tuple_and_dict():
    gear = spaces.Discrete(6, start=1)
    gear.seed(0)
    assert {int(gear.sample()) for _ in range(200)} == {1, 2, 3, 4, 5, 6}
    assert gear.contains(1) and gear.contains(6) and not gear.contains(0) and not gear.contains(7)
    bits = spaces.MultiBinary(3)
    assert bits.contains(np.array([0, 1, 1])) and not bits.contains(np.array([0, 2, 1]))
    d = spaces.Dict({"b": bits, "a": gear})
    assert list(d.keys()) == ["a", "b"], "a plain dict's keys are sorted"
    ordered = spaces.Dict(collections.OrderedDict([("b", bits), ("a", gear)]))
    assert list(ordered.keys()) == ["b", "a"]
    assert d.contains(d.sample()) and not d.contains({"a": 1})
    pair = spaces.Tuple([gear, bits])
    assert pair.contains(pair.sample()) and len(pair) == 2


def test_flatten_and_unflatten_round_trip_in_gymnasiums_layout():
    spec = rpi.vehicle_action_spec(auto_gear=False, num_gears=6)
    action = {"throttle": np.array([0.25], np.float32), "steer": np.array([-0.5], np.float32),
              "brake": np.array([0.0], np.float32), "hand_brake": np.array([1.0], np.float32),
              "reverse": np.array([1], np.int8), "target_gear": np.int64(3)}
    flat = spaces.flatten(spec, action)
    # In the keys' order (sorted, as ROAR_PY's spec is built): Boxes as they are, MultiBinary as 0/1, a
    # Discrete(6, start=1) as a one-hot of 6: gymnasium's layout.
    assert flat.tolist() == [0.0, 1.0, 1.0, -0.5, 0, 0, 1, 0, 0, 0, 0.25]
    assert spaces.flatdim(spec) == 11 and spaces.flatten_space(spec).shape == (11,)
    back = spaces.unflatten(spec, flat)
    assert int(back["target_gear"]) == 3 and back["steer"][0] == pytest.approx(-0.5)
    assert spec.contains(back)


def test_without_gymnasium_import_gymnasium_gives_the_fallback():
    import gymnasium as gym

    assert gym.spaces.Box is spaces.Box and gym.Space is spaces.Space
    assert gym.spaces.utils.flatten is spaces.flatten

    class Env(gym.Env):
        def reset(self, *, seed=None, options=None):
            super().reset(seed=seed)
            return self.np_random.integers(1000), {}

    first, second = Env(), Env()
    assert first.reset(seed=7)[0] == second.reset(seed=7)[0], "reset(seed) seeds np_random as gymnasium does"


def test_spaces_pickle_with_gymnasiums_module_names_and_attributes():
    # ROAR_PY's remote protocol ships spaces as pickles: a gymnasium Box's attributes and module.
    box = spaces.Box(low=np.array([0.0, -1.0]), high=np.array([1.0, 1.0]), dtype=np.float32)
    data = pickle.dumps(box)
    assert b"gymnasium.spaces.box" in data
    for attribute in ("dtype", "_shape", "low", "high", "low_repr", "high_repr", "bounded_below", "bounded_above",
                      "_np_random"):
        assert attribute in box.__dict__
    again = pickle.loads(data)
    assert again == box and again.low_repr == box.low_repr
    gear = pickle.loads(pickle.dumps(spaces.Discrete(6, start=1)))
    assert gear.n == 6 and gear.start == 1 and gear.shape == ()


# ---- actions as ROAR_PY over CARLA takes them ----------------------------------------------------------

def reader(auto_gear=True):
    return conversions.ActionReader("vehicle 'test'", auto_gear, 6)


GO = {"throttle": np.array([0.4]), "steer": np.array([0.25]), "brake": 0.0, "hand_brake": np.array([0]),
      "reverse": np.array([0])}


def test_an_automatic_car_ignores_target_gear_with_one_warning():
    # ROAR_PY's CARLA backend sets manual_gear_shift False on an automatic car: target_gear never reaches CARLA.
    read = reader(auto_gear=True)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for _ in range(3):
            values = read.read({**GO, "target_gear": 4})
    assert "target_gear" not in values
    assert len(caught) == 1 and issubclass(caught[0].category, conversions.RoarPyCompatibilityWarning)
    assert "'target_gear' ignored" in str(caught[0].message) and "automatic gearbox" in str(caught[0].message)
    control = conversions.to_vehicle_control(values, auto_gear=True)
    assert not control.manual_gear_shift and control.steer == pytest.approx(-0.25), "ROAR_PY steers right positive"


def test_values_out_of_range_are_clamped_as_carla_clamps_them():
    read = reader()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        values = read.read({**GO, "throttle": 1.5, "steer": -3.0})
        read.read({**GO, "throttle": 2.0})
    assert values["throttle"] == 1.0 and values["steer"] == -1.0
    assert sorted(str(w.message).split("field '")[1].split("'")[0] for w in caught) == ["steer", "throttle"], \
        "once per field"


def test_switches_read_as_roar_pys_carla_backend_reads_them():
    read = reader()
    assert read.read({**GO, "hand_brake": 0.49})["hand_brake"] == 0.0
    assert read.read({**GO, "hand_brake": 0.5})["hand_brake"] == 1.0, "float(hand_brake) >= 0.5"
    assert read.read({**GO, "reverse": np.array([-1])})["reverse"] == 1.0, "bool(reverse)"
    manual = reader(auto_gear=False)
    control = conversions.to_vehicle_control(manual.read({**GO, "target_gear": np.int64(3)}), auto_gear=False)
    assert control.manual_gear_shift and control.gear == 3


def test_vehicle_action_spec_flattens_in_roar_pys_order():
    # ROAR_PY builds the spec from a plain dict, which gymnasium's Dict sorts: RL policies trained on
    # flattened actions, and ROAR_PY's remote protocol, depend on that layout.
    spec = rpi.vehicle_action_spec(auto_gear=False)
    assert list(spec.spaces) == ["brake", "hand_brake", "reverse", "steer", "target_gear", "throttle"]
    flat = spaces.flatten(rpi.vehicle_action_spec(), {**GO, "brake": np.array([0.1])})
    assert flat.tolist() == pytest.approx([0.1, 0.0, 0.0, 0.25, 0.4])


def test_what_carla_cannot_take_is_refused_naming_the_field():
    read = reader()
    with pytest.raises(ValueError, match="'steer' must be finite"):
        read.read({**GO, "steer": float("nan")})
    with pytest.raises(ValueError, match="'brake' is missing"):
        read.read({k: v for k, v in GO.items() if k != "brake"})
    with pytest.raises(ValueError, match="'throttle' is not a number"):
        read.read({**GO, "throttle": "full"})
    with pytest.raises(ValueError, match="'throttle' must be one number, got 2"):
        read.read({**GO, "throttle": np.array([0.1, 0.2])})
    with pytest.raises(ValueError, match="an action is a dict"):
        read.read([0.1, 0.2])
    with pytest.raises(ValueError, match="'target_gear' is missing"):
        reader(auto_gear=False).read(GO)


# ---- waypoints and their tracker -----------------------------------------------------------------------

def test_waypoint_line_representation_round_trips(tmp_path):
    w = rpi.RoarPyWaypoint(np.array([10.0, 5.0, 0.0]), np.array([0.0, 0.0, np.pi / 2]), 12.0)
    left, right = w.line_representation
    assert np.allclose(left, [4.0, 5.0, 0.0]) and np.allclose(right, [16.0, 5.0, 0.0]), "left of a car heading +y is -x"
    back = rpi.RoarPyWaypoint.from_line_representation(left, right, w.roll_pitch_yaw)
    assert back == w, "ROAR_PY's __eq__: every field allclose"
    assert back != rpi.RoarPyWaypoint(w.location + 0.1, w.roll_pitch_yaw, 12.0)
    path = tmp_path / "w.npz"
    np.savez_compressed(path, **rpi.RoarPyWaypoint.save_waypoint_list([w, back]))
    loaded = rpi.RoarPyWaypoint.load_waypoint_list(np.load(path))
    assert loaded == [w, w]
    with pytest.raises(KeyError, match="no 'lane_widths'"):
        rpi.RoarPyWaypoint.load_waypoint_list({"locations": np.zeros((1, 3)), "rotations": np.zeros((1, 3))})


def test_interpolate_weighs_the_first_waypoint_by_alpha_as_roar_py_does():
    a = rpi.RoarPyWaypoint(np.zeros(3), np.array([0.0, 0.0, 0.2]), 10.0)
    b = rpi.RoarPyWaypoint(np.array([10.0, 0.0, 0.0]), np.array([0.0, 0.0, 0.4]), 12.0)
    blend = rpi.RoarPyWaypoint.interpolate(a, b, 0.25)
    assert np.allclose(blend.location, [7.5, 0, 0]) and blend.lane_width == pytest.approx(11.5)
    assert blend.roll_pitch_yaw[2] == pytest.approx(0.35)
    assert rpi.RoarPyWaypoint.interpolate(a, b, 1.0) == a


def square_track(side=100.0, spacing=2.0, width=10.0):
    """A closed square, anticlockwise, a waypoint every `spacing` metres."""
    points = []
    for edge, yaw in enumerate([0.0, np.pi / 2, np.pi, -np.pi / 2]):
        start = np.array([[0, 0], [side, 0], [side, side], [0, side]][edge], dtype=float)
        direction = np.array([np.cos(yaw), np.sin(yaw)])
        for s in np.arange(0.0, side, spacing):
            points.append(rpi.RoarPyWaypoint(np.array([*(start + s * direction), 0.0]), np.array([0.0, 0.0, yaw]), width))
    return points


def test_the_tracker_measures_distance_along_the_waypoints():
    waypoints = square_track()
    tracker = rpi.RoarPyWaypointsTracker(waypoints)
    projection = tracker.trace_point(np.array([31.0, 1.5, 0.0]), 0)
    assert projection == rpi.RoarPyWaypointsProjection(15, pytest.approx(1.0))
    assert tracker.total_distance_from_first_waypoint(projection) == pytest.approx(31.0)
    ahead = tracker.trace_forward_projection(projection, 80.0)
    assert tracker.total_distance_from_first_waypoint(ahead) == pytest.approx(111.0), "round the corner"
    assert ahead.waypoint_idx == 55
    assert tracker.delta_distance_projection(projection, ahead) == pytest.approx(80.0)
    assert tracker.delta_distance_projection(ahead, projection) == pytest.approx(-80.0)
    behind = tracker.trace_forward_projection(projection, -10.0)
    assert tracker.total_distance_from_first_waypoint(behind) == pytest.approx(21.0), "modulo the lap, as ROAR_PY"
    lap = tracker.trace_forward_projection(tracker.trace_point(np.array([1.0, 0.0, 0.0])), 399.0)
    assert tracker.total_distance_from_first_waypoint(lap) == pytest.approx(0.0), "399 m on from 1 m: the lap's start"
    wrapped = tracker.trace_point(np.array([1.0, -2.0, 0.0]), 150)
    assert wrapped.waypoint_idx == 0, "searched outwards both ways from the start index"


def roar_pys_forward_walk(tracker, projection, distance):
    """ROAR_PY's trace_forward_projection as it is written: segment by segment."""
    count = len(tracker.waypoints)
    remaining = distance % tracker._total_distance
    index, along = projection.waypoint_idx, projection.distance_from_waypoint
    while remaining > 0:
        to_progress = tracker._distance_between_waypoints[index] - along
        if remaining < to_progress:
            along += remaining
            break
        remaining -= to_progress
        index, along = (index + 1) % count, 0
    return index, along


def test_forward_projections_walk_as_roar_pys():
    rng = np.random.default_rng(7)
    # Irregular spacing round a loop, as a map's waypoints are.
    angles = np.sort(rng.uniform(0, 2 * np.pi, 300))
    waypoints = [rpi.RoarPyWaypoint(np.array([100 * np.cos(t), 60 * np.sin(t), 0.0]), np.array([0.0, 0.0, t + np.pi / 2]),
                                    8.0) for t in angles]
    tracker = rpi.RoarPyWaypointsTracker(waypoints)
    cases = [(int(i), float(a), float(d)) for i, a, d in zip(rng.integers(0, 300, 400), rng.uniform(-2.0, 4.0, 400),
                                                            rng.uniform(-600.0, 600.0, 400))]
    cases += [(5, 0.0, 0.0), (299, 1.0, tracker._total_distance), (10, 0.0, tracker._distance_between_waypoints[10])]
    for index, along, distance in cases:
        got = tracker.trace_forward_projection(rpi.RoarPyWaypointsProjection(index, along), distance)
        want = roar_pys_forward_walk(tracker, rpi.RoarPyWaypointsProjection(index, along), distance)
        assert got.waypoint_idx == want[0] and got.distance_from_waypoint == pytest.approx(want[1], abs=1e-9), \
            (index, along, distance)


def test_the_tracker_blends_with_roar_pys_weights():
    waypoints = square_track()
    tracker = rpi.RoarPyWaypointsTracker(waypoints)
    start_of_segment = tracker.get_interpolated_waypoint(rpi.RoarPyWaypointsProjection(10, 0.0))
    # ROAR_PY's get_interpolated_waypoint gives interpolate(previous, next, 0): the next waypoint.
    assert start_of_segment == waypoints[11]
    quarter = tracker.get_interpolated_waypoint(rpi.RoarPyWaypointsProjection(10, 0.5))
    assert np.allclose(quarter.location, waypoints[10].location * 0.25 + waypoints[11].location * 0.75)


def test_shapely_2s_names_import_as_roar_py_rl_imports_them():
    import shapely.geometry
    from shapely import Point, Polygon  # ROAR_PY_RL's sim_env.py; Debian's shapely 1.8 has no such names

    assert Polygon is shapely.geometry.Polygon and Point is shapely.geometry.Point
    assert Polygon([(0, 0), (2, 0), (2, 2), (0, 2)]).distance(Point(3, 1)) == pytest.approx(1.0)


def test_the_polygon_distance_is_shapelys():
    # ROAR_PY measures with shapely's Polygon.distance; Debian's shapely (1.8) checks the numpy version.
    rng = np.random.default_rng(3)
    for _ in range(300):
        a = rpi.RoarPyWaypoint(np.append(rng.uniform(-20, 20, 2), 0), np.array([0, 0, rng.uniform(-3, 3)]),
                               rng.uniform(2, 15))
        b = rpi.RoarPyWaypoint(a.location + np.append(rng.uniform(-6, 6, 2), 0), np.array([0, 0, rng.uniform(-3, 3)]),
                               rng.uniform(2, 15))
        point = rng.uniform(-30, 30, 3)
        p1, p2 = a.line_representation
        p3, p4 = b.line_representation
        polygon = Polygon([p1[:2], p2[:2], p4[:2], p3[:2]])
        if not polygon.is_valid:
            continue  # a bow tie: shapely measures it by its own rules
        assert rpi.RoarPyWaypoint.distance_to_waypoint_polygon(a, b, point) == pytest.approx(
            polygon.distance(Point(point[:2])), abs=1e-9)


def test_rotations_are_transforms3ds():
    rng = np.random.default_rng(1)
    for _ in range(50):
        rpy = rng.uniform(-1.4, 1.4, 3)
        q = transforms.euler2quat(*rpy)
        assert np.allclose(q, transforms3d.euler.euler2quat(*rpy))
        assert np.allclose(transforms.quat2euler(q), transforms3d.euler.quat2euler(q))
        assert np.allclose(transforms.euler2mat(*rpy), transforms3d.euler.euler2mat(*rpy))
        v = rng.normal(size=3)
        assert np.allclose(transforms.rotate_vector(v, transforms.qinverse(q)),
                           transforms3d.quaternions.rotate_vector(v, transforms3d.quaternions.qinverse(q)))


# ---- sensors' data, wrappers and observations -----------------------------------------------------------

class FakeSensor(rpi.RoarPyLocationInWorldSensor):
    def __init__(self, name, value):
        super().__init__(name, 0.05)
        self.value = value
        self.last = None
        self.closed = False

    async def receive_observation(self):
        self.last = rpi.RoarPyLocationInWorldSensorData(*self.value)
        return self.last

    def get_last_observation(self):
        return self.last

    def close(self):
        self.closed = True

    def is_closed(self):
        return self.closed


class FakeVehicle(rpi.RoarPyVehicleAutoGearActor):
    def __init__(self):
        super().__init__("fake")
        self.sensors = [FakeSensor("gps", (1.0, 2.0, 3.0)), FakeSensor("gps", (4.0, 5.0, 6.0)),
                        FakeSensor("speed", (0.0, 0.0, 0.0))]
        self.actions = []

    def get_sensors(self):
        return [s for s in self.sensors if not s.is_closed()]

    async def _apply_action(self, action):
        self.actions.append(action)
        return True

    def close(self):
        pass

    def is_closed(self):
        return False


class ForwardingWrapper(rpi.RoarPyActor):
    """The competition starter kit's pattern: no RoarPyActor.__init__, every call forwarded."""

    def __init__(self, wrapped):
        self.wrapped = wrapped

    def get_sensors(self):
        return self.wrapped.get_sensors()

    def get_action_spec(self):
        return self.wrapped.get_action_spec()

    async def _apply_action(self, action):
        return await self.wrapped.apply_action(action)

    def close(self):
        self.wrapped.close()

    def is_closed(self):
        return self.wrapped.is_closed()


def test_observations_name_repeated_sensors_as_roar_py_does_and_wrappers_forward():
    vehicle = FakeVehicle()
    assert rpi.observation_keys(vehicle.sensors) == ["gps_1", "gps_2", "speed"]
    for actor in (vehicle, ForwardingWrapper(vehicle), rpi.RoarPyActorWrapper(vehicle)):
        obs = asyncio.run(actor.receive_observation())
        assert list(obs) == ["gps_1", "gps_2", "speed"]
        gym = actor.convert_obs_to_gym_obs(obs)
        assert np.allclose(gym["gps_2"], [4, 5, 6]) and gym["gps_2"].dtype == np.float64, "ROAR_PY's np.array([x,y,z])"
        assert list(actor.get_gym_observation_spec().keys()) == ["gps_1", "gps_2", "speed"]
        assert np.allclose(actor.get_last_gym_observation()["gps_1"], [1, 2, 3])
        assert asyncio.run(actor.apply_action(actor.get_action_spec().sample()))
    assert len(vehicle.actions) == 3


def test_wrappers_forward_public_attributes_only_and_filter_sensors():
    vehicle = FakeVehicle()
    wrapped = rpi.RoarPyActorWrapper(rpi.RoarPyActorWrapper(vehicle))
    assert wrapped.unwrapped is vehicle and wrapped.sensors is vehicle.sensors and wrapped.name == "fake"
    with pytest.raises(AttributeError, match="private"):
        wrapped._last_action_t_of_nothing
    filtered = rpi.RoarPyActorSensorFilterWrapper(vehicle, exclude_sensors=[vehicle.sensors[2]])
    obs = asyncio.run(filtered.receive_observation())
    assert list(obs) == ["gps_1", "gps_2"] and list(filtered.get_gym_observation_spec().keys()) == ["gps_1", "gps_2"]
    assert list(filtered.get_last_gym_observation()) == ["gps_1", "gps_2"]
    sensor = rpi.RoarPySensorWrapper(vehicle.sensors[0])
    assert asyncio.run(sensor.receive_observation()).x == 1.0 and sensor.name == "gps"


def test_the_thread_safe_wrapper_serialises_marked_methods():
    class Counter(rpi.RoarPyWorld):
        def __init__(self):
            self.inside = 0
            self.most = 0

        @rpi.roar_py_thread_sync
        def work(self):
            self.inside += 1
            self.most = max(self.most, self.inside)
            threading.Event().wait(0.002)
            self.inside -= 1

    counter = Counter()
    rpi.RoarPyThreadSafeWrapper(counter, threading.RLock())
    with pytest.raises(RuntimeError, match="twice"):
        rpi.RoarPyThreadSafeWrapper(counter, threading.RLock())
    threads = [threading.Thread(target=lambda: [counter.work() for _ in range(20)]) for _ in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert counter.most == 1, "never two callers inside at once"


def test_the_add_item_wrapper_reports_what_marked_methods_add_and_remove():
    class Shelf:
        @rpi.roar_py_append_item
        def add(self, item):
            return item * 2

        @rpi.roar_py_remove_item
        def remove(self, item):
            return None

    shelf, added, removed = Shelf(), [], []
    rpi.RoarPyAddItemWrapper(shelf, added.append, removed.append)
    shelf.add(3)
    shelf.remove(9)
    assert added == [6] and removed == [9]


def test_frame_quaternion_and_roll_pitch_yaw_sensors_convert_each_other():
    class Rpy(rpi.RoarPyRollPitchYawSensor):
        async def receive_observation(self):
            return rpi.RoarPyRollPitchYawSensorData(np.array([0.1, -0.2, 2.5]))

        def close(self):
            pass

        def is_closed(self):
            return False

    quat = rpi.RoarPyFrameQuatSensorFromRollPitchYaw(Rpy("rpy", 0.05))
    assert quat.name == "rpy -> framequat" and quat.control_timestep == 0.05
    q = asyncio.run(quat.receive_observation()).frame_quaternion
    assert np.allclose(q, transforms3d.euler.euler2quat(0.1, -0.2, 2.5)) and quat.get_gym_observation_spec().shape == (4,)
    back = rpi.RoarPyRollPitchYawSensorFromFrameQuat(quat)
    assert np.allclose(asyncio.run(back.receive_observation()).roll_pitch_yaw, [0.1, -0.2, 2.5])


class SpeedAndLap(rpi.RoarPyCustomLambdaSensor):
    """A custom sensor as ROAR's programs write one: a subclass with its own receive_observation."""

    def __init__(self, name, speed):
        super().__init__(name, 0.05, spaces.Dict({"speed": spaces.Box(0, 100, (1,)), "lap": spaces.Discrete(5)}))
        self.speed = speed

    async def receive_observation(self):
        return self.observed({"speed": np.array([self.speed], np.float32), "lap": 2})


def test_a_custom_lambda_sensor_subclass_reads_its_value():
    space = spaces.Dict({"speed": spaces.Box(0, 100, (1,)), "lap": spaces.Discrete(5)})
    sensor = SpeedAndLap("custom", 12.5)
    data = asyncio.run(sensor.receive_observation())
    assert data.flattened.tolist() == [0, 0, 1, 0, 0, 12.5], "a plain dict's keys sorted: lap, then speed"
    assert int(data.unflattened["lap"]) == 2
    assert sensor.get_last_gym_observation()["speed"][0] == pytest.approx(12.5)
    again = rpi.RoarPyCustomLambdaSensorData.from_data(data.to_data(Scheme.MSGPACK_COMPRESSED), Scheme.MSGPACK_COMPRESSED)
    assert again.space == space and np.array_equal(again.flattened, data.flattened)
    with pytest.raises(ValueError, match="not a value of"):
        asyncio.run(SpeedAndLap("bad", 500.0).receive_observation())
    with pytest.raises(NotImplementedError, match="subclass implements receive_observation"):
        asyncio.run(rpi.RoarPyCustomLambdaSensor("abstract", 0.05, space).receive_observation())


def test_the_occupancy_map_draws_the_road_ahead_upwards():
    # ROAR_PY draws the stretches whose cross-sections cross the edge of a square twice the map's size
    # around the car: the competition's 2 m map on a road wider than 4 m. Here a 6 m map 1 m inside the
    # left edge of a 10 m road along x.
    waypoints = square_track(side=200.0, spacing=2.0, width=10.0)
    producer = rpi.RoarPyOccupancyMapProducer(waypoints, 48, 48, 6.0, 6.0)
    image = np.asarray(producer.plot_occupancy_map(np.array([100.0, 4.0]), 0.0))
    assert image.shape == (48, 48)
    # Forward (x) is up, left (y) is to the left: the road's left edge, 1 m to the left, is 8 columns left.
    assert np.all(image[:, 17:] == 255) and np.all(image[:, :15] == 0)
    turned = np.asarray(producer.plot_occupancy_map(np.array([100.0, 4.0]), np.pi / 2))
    assert np.all(turned[17:, :] == 255) and np.all(turned[:15, :] == 0), "heading +y: the edge 1 m ahead"
    data = rpi.RoarPyOccupancyMapSensorData.from_image(producer.plot_occupancy_map(np.array([100.0, 4.0]), 0.0))
    assert data.convert_obs_to_gym_obs().shape == (48, 48, 1) and data.get_gym_observation_spec().shape == (48, 48, 1)
    assert rpi.RoarPyOccupancyMapSensorData.from_data(data.to_data(Scheme.MSGPACK), Scheme.MSGPACK).occupancy_map.size == (48, 48)


def roar_pys_occupancy_walk(producer, location_min, location_max):
    """ROAR_PY's occupancy map walk, one waypoint at a time as its loop goes: from ten before the last start the
    first waypoint whose cross-section crosses the square's sides, then the run of those after it that do."""
    def crosses(a, b, c, d):
        u, v = b - a, d - c
        det = u[0] * v[1] - u[1] * v[0]
        if det == 0:
            return False
        r = ((a[1] - c[1]) * v[0] - (a[0] - c[0]) * v[1]) / det
        s = ((a[1] - c[1]) * u[0] - (a[0] - c[0]) * u[1]) / det
        return 0 <= r <= 1 and 0 <= s <= 1

    def in_range(w):
        start, end = w.line_representation[0][:2], w.line_representation[1][:2]
        side_1, side_2 = np.array([location_min[0], location_max[1]]), np.array([location_max[0], location_min[1]])
        return any(crosses(start, end, a, b) for a, b in ((location_min, side_1), (side_1, location_max),
                                                          (location_max, side_2), (side_2, location_min)))
    waypoints, count, last = producer.waypoints, len(producer.waypoints), None
    search_from = 0 if producer.reference_start == -1 else producer.reference_start - 10
    for i in range(count):
        if in_range(waypoints[(search_from + i) % count]):
            producer.reference_start = (search_from + i) % count
            last = waypoints[producer.reference_start]
            break
    pairs = []
    for i in range(1, count + 1):
        waypoint = waypoints[(producer.reference_start + i) % count]
        if last is not None:
            pairs.append((last, waypoint))
            last = None
        if not in_range(waypoint):
            break
        last = waypoint
    return pairs


def test_the_occupancy_map_draws_what_roar_pys_loop_draws():
    # The producer tests every waypoint at once; ROAR_PY's walk, one at a time, must give the same pairs along
    # Monza, off it and across its ends, for the runner's 2 m map and a wide one.
    waypoints = rpi.RoarPyWaypoint.load_waypoint_list(np.load(os.path.join(ROOT, "maps", "monza", "waypoints.npz")))
    rng = np.random.default_rng(7)
    for width_world in (2.0, 20.0, 300.0):
        producer = rpi.RoarPyOccupancyMapProducer(waypoints, 50, 50, width_world, width_world)
        producer.reference_start = -1
        for k in range(0, 2 * len(waypoints), 37):
            place = waypoints[k % len(waypoints)].location[:2] + rng.normal(0, 3, 2) + (
                rng.normal(0, 60, 2) if k % 5 == 0 else 0)
            half = np.array([width_world, width_world])
            expected = roar_pys_occupancy_walk(producer, place - half, place + half)
            got = producer._pairs_in_range(place - half, place + half)
            assert [(id(a), id(b)) for a, b in got] == [(id(a), id(b)) for a, b in expected], (width_world, k)
            assert producer.start_index == producer.reference_start


def test_camera_data_is_roar_pys():
    rgb = rpi.RoarPyCameraSensorDataRGB(np.zeros((6, 8, 3), np.uint8))
    assert rgb.get_size() == (8, 6) and rgb.get_image().size == (8, 6)
    grey = rpi.RoarPyCameraSensorDataGreyscale.from_image(rgb.get_image())
    assert grey.to_gym().shape == (6, 8), "CARLA's backend gives greyscale as H x W"
    assert grey.get_gym_observation_spec().shape == (6, 8, 1)
    depth = rpi.RoarPyCameraSensorDataDepth(np.linspace(0, 1000, 48).reshape(6, 8), False)
    assert np.asarray(depth.get_image()).max() == 255 and depth.get_image().mode == "L" and depth.get_size() == (8, 6)
    assert depth.to_gym().shape == (6, 8), "CARLA's backend gives depth as H x W float64"
    ss = rpi.RoarPyCameraSensorDataSemanticSegmentation(np.full((6, 8, 1), 7, np.uint64), rpi.CARLA_SEMANTIC_LABEL_COLOR_MAP)
    assert tuple(np.asarray(ss.get_image())[0, 0]) == (128, 64, 128), "CARLA's tag 7 is the road"
    lidar = rpi.RoarPyLiDARSensorData(32, 0.5, np.ones((3, 4), np.float32))
    assert lidar.convert_obs_to_gym_obs().shape == (3, 4) and lidar.channels == 32


def test_readings_serialise_in_roar_pys_schemes():
    velocity = rpi.RoarPyVelocimeterSensorData(np.array([1.0, 2.0, 3.5]))
    # pyserde's MessagePack: the dataclass as a map of its fields, arrays as lists.
    assert velocity.to_data(Scheme.MSGPACK) == msgpack.packb({"velocity": [1.0, 2.0, 3.5]}, use_bin_type=True)
    for scheme in Scheme:
        if scheme == Scheme.INTERNAL_COMPRESSED:
            continue
        back = rpi.RoarPyVelocimeterSensorData.from_data(velocity.to_data(scheme), scheme)
        assert np.array_equal(back.velocity, velocity.velocity), scheme
    gnss = rpi.RoarPyGNSSSensorData(12.0, 37.8, -122.3)
    assert rpi.RoarPyGNSSSensorData.from_data(gnss.to_data(Scheme.JSON_COMPRESSED), Scheme.JSON_COMPRESSED) == gnss
    image = rpi.RoarPyCameraSensorDataRGB(np.full((16, 16, 3), 200, np.uint8))
    back = rpi.RoarPyCameraSensorDataRGB.from_data(image.to_data(Scheme.MSGPACK_COMPRESSED), Scheme.MSGPACK_COMPRESSED)
    assert back.image_rgb.shape == (16, 16, 3) and abs(int(back.image_rgb[8, 8, 0]) - 200) <= 2, "JPEG"
    assert "RoarPyRadarSensorData" in rpi.RoarPyRemoteSupportedSensorData._supported_data_types
    with pytest.raises(ValueError, match="no field 'velocity'"):
        rpi.RoarPyVelocimeterSensorData.from_data({"speed": 1}, Scheme.DICT)


def test_the_visualizer_pastes_cameras_left_and_maps_right():
    class Viewed(FakeVehicle):
        def get_last_observation(self):
            return {"camera": rpi.RoarPyCameraSensorDataRGB(np.full((60, 80, 3), 10, np.uint8)),
                    "map": rpi.RoarPyOccupancyMapSensorData.from_image(rpi.RoarPyOccupancyMapProducer(
                        square_track(), 20, 20, 10.0, 10.0).image.point(lambda v: 255)),
                    "gps": rpi.RoarPyLocationInWorldSensorData(0.0, 0.0, 0.0)}

    picture = np.asarray(rpi.RoarPyVisualizer(Viewed()).render())
    assert picture.shape == (60, 80, 3)
    assert picture[0, 79, 0] == 255 and picture[30, 30, 0] == 10
    assert rpi.RoarPyVisualizer(FakeVehicle()).render() is None


def test_what_roar_programs_import_beside_roar_py_is_installed():
    """scripts/setup installs what ROAR's entries and ROAR_PY_RL import next to ROAR_PY (Debian's builds)."""
    import importlib
    for module in ("cv2", "transforms3d", "scipy.spatial.transform", "matplotlib.pyplot", "nest_asyncio",
                   "shapely.geometry", "pygame", "websockets", "msgpack"):
        assert importlib.import_module(module) is not None, module
    import cv2
    image = cv2.cvtColor(np.zeros((4, 6, 3), np.uint8), cv2.COLOR_RGB2GRAY)
    assert image.shape == (4, 6)


def test_an_observation_space_is_sorted_by_key_as_roar_pys():
    """ROAR_PY builds a plain dict, which gymnasium's Dict sorts: a flattened observation is laid out by key,
    whatever order the sensors came in."""
    vehicle = FakeVehicle()
    vehicle.sensors = [FakeSensor("velocity", (7.0, 8.0, 9.0)), FakeSensor("location", (1.0, 2.0, 3.0))]
    spec = vehicle.get_gym_observation_spec()
    assert list(spec.keys()) == ["location", "velocity"]
    asyncio.run(vehicle.receive_observation())
    flat = rpi.spaces.flatten(spec, vehicle.get_last_gym_observation())
    assert np.allclose(flat, [1, 2, 3, 7, 8, 9])


class CountingSensor(FakeSensor):
    """A location sensor that counts its gym conversions (a camera's would render a frame)."""

    def __init__(self, name, value):
        super().__init__(name, value)
        self.conversions = 0

    def convert_obs_to_gym_obs(self, obs):
        self.conversions += 1
        return super().convert_obs_to_gym_obs(obs)


def test_a_gym_observation_converts_only_the_keys_read():
    import gymnasium as gym

    vehicle = FakeVehicle()
    camera, gps = CountingSensor("camera", (1.0, 2.0, 3.0)), CountingSensor("gps", (4.0, 5.0, 6.0))
    vehicle.sensors = [camera, gps]
    asyncio.run(vehicle.receive_observation())
    obs = vehicle.get_last_gym_observation()
    assert list(obs) == ["camera", "gps"] and "camera" in obs and len(obs) == 2
    assert (camera.conversions, gps.conversions) == (0, 0), "nothing converted before it is read"
    assert np.allclose(obs["gps"], [4, 5, 6]) and np.allclose(obs.get("gps"), [4, 5, 6])
    assert (camera.conversions, gps.conversions) == (0, 1), "read once, converted once"
    kept = obs.copy()
    kept["extra"] = 1
    assert "extra" not in obs and camera.conversions == 0
    # gymnasium's FilterObservation keeping one key converts that key alone.
    env = gym.Env()
    env.observation_space = vehicle.get_gym_observation_spec()
    filtered = gym.wrappers.FilterObservation(env, ["gps"]).observation(vehicle.get_last_gym_observation())
    assert list(filtered) == ["gps"] and camera.conversions == 0
    # Every other way of reading values converts them: as a plain dict, it holds the converted values.
    for read in (dict, lambda o: {**o}, lambda o: list(o.values()), lambda o: list(o.items()), pickle.dumps, repr,
                 lambda o: o.setdefault("camera"), lambda o: o.popitem() and o.popitem()):
        fresh = vehicle.get_last_gym_observation()
        before = camera.conversions
        read(fresh)
        assert camera.conversions == before + 1, read
    plain = dict(vehicle.get_last_gym_observation())
    assert all(isinstance(v, np.ndarray) for v in plain.values())
    assert np.allclose(pickle.loads(pickle.dumps(vehicle.get_last_gym_observation()))["camera"], [1, 2, 3])
    popped = vehicle.get_last_gym_observation()
    assert np.allclose(popped.pop("camera"), [1, 2, 3]) and list(popped) == ["gps"]


def test_propose_name_moves_the_first_of_a_repeated_name_as_roar_pys():
    keys = {"cam": "first"}
    assert rpi.propose_name_and_modify_dict(keys, "cam") == "cam_2" and keys == {"cam_1": "first"}
    keys["cam_2"] = "second"
    assert rpi.propose_name_and_modify_dict(keys, "cam") == "cam_3" and list(keys) == ["cam_1", "cam_2"]
    assert rpi.propose_name_and_modify_dict(keys, "gps") == "gps"
    names = ["cam", "gps"]
    assert rpi.propose_name_and_modify_list(names, "cam") == "cam_2" and names == ["gps", "cam_1"]
    assert rpi.propose_name_and_modify_list(names, "lidar") == "lidar" and names == ["gps", "cam_1"]


def test_gymnasiums_wrappers_behave_as_gymnasiums():
    import gymnasium as gym

    class Counter(gym.Env):
        """Observes {"n": step count, "twice": 2n}; reward 1 a step; ends at 5 steps."""

        def __init__(self):
            self.observation_space = gym.spaces.Dict({"twice": gym.spaces.Box(0, 100, (1,)),
                                                      "n": gym.spaces.Box(0, 100, (1,))})
            self.action_space = gym.spaces.Box(-1, 1, (1,))
            self.n, self.actions = 0, []

        def _obs(self):
            return {"n": np.array([self.n], np.float32), "twice": np.array([2 * self.n], np.float32)}

        def reset(self, *, seed=None, options=None):
            super().reset(seed=seed)
            self.n = 0
            return self._obs(), {}

        def step(self, action):
            self.actions.append(action)
            self.n += 1
            return self._obs(), 1.0, self.n >= 5, False, {}

    class Doubled(gym.ActionWrapper):
        def action(self, action):
            return 2 * action

    class Halved(gym.RewardWrapper):
        def reward(self, reward):
            return reward / 2

    base = Counter()
    env = Halved(Doubled(base))
    env.reset()
    _, reward, *_ = env.step(np.array([0.25]))
    assert reward == 0.5 and base.actions[-1][0] == 0.5
    env.observation_space = gym.spaces.Box(0, 1, (2,))  # a wrapper's own space, as gymnasium's wrappers set
    assert env.observation_space.shape == (2,) and isinstance(base.observation_space, gym.spaces.Dict)

    filtered = gym.wrappers.FilterObservation(Counter(), ["twice"])
    assert list(filtered.observation_space.spaces) == ["twice"] and list(filtered.reset()[0]) == ["twice"]
    with pytest.raises(ValueError, match=r"\['nope'\] are not keys"):
        gym.wrappers.FilterObservation(Counter(), ["nope"])
    flat = gym.wrappers.FlattenObservation(Counter())
    flat.reset()
    assert np.allclose(flat.step(0)[0], [1, 2]), "gymnasium's layout: the Dict's sorted keys, n then twice"

    limited = gym.wrappers.RecordEpisodeStatistics(gym.wrappers.TimeLimit(Counter(), max_episode_steps=3))
    limited.reset()
    ends = [limited.step(0) for _ in range(3)]
    assert [e[3] for e in ends] == [False, False, True] and not ends[-1][2], "truncated at 3, not terminated"
    assert ends[-1][4]["episode"]["r"] == 3.0 and ends[-1][4]["episode"]["l"] == 3 and list(limited.return_queue) == [3.0]
    with pytest.raises(ValueError, match="max_episode_steps"):
        gym.wrappers.TimeLimit(Counter(), max_episode_steps=0)

    normalised = gym.wrappers.NormalizeObservation(gym.wrappers.FlattenObservation(Counter()))
    normalised.reset()
    seen = [normalised.step(0)[0] for _ in range(4)]
    values = np.array([[0, 0]] + [[n, 2 * n] for n in range(1, 5)], np.float64)
    assert np.allclose(normalised.obs_rms.mean, values.mean(axis=0), atol=1e-3)
    assert np.allclose(seen[-1], (values[-1] - values.mean(axis=0)) / np.sqrt(values.var(axis=0) + 1e-8), atol=1e-3)


def test_a_resettable_actor_resets_through_roar_pys_hook_or_ours():
    class RoarPyStyle(rpi.RoarPyResettableActor):
        async def _RoarPyResettableActor__reset(self):  # what a subclass overriding ROAR_PY's mangled hook writes
            self.done = "roar_py"

    class OursStyle(rpi.RoarPyResettableActor):
        async def _reset(self):
            self.done = "ours"

    for cls, expected in ((RoarPyStyle, "roar_py"), (OursStyle, "ours")):
        actor = cls()
        asyncio.run(actor.reset())
        assert actor.done == expected


def test_an_actor_wrapper_observes_its_own_sensors_as_roar_pys():
    """ROAR_PY's RoarPyActorWrapper inherits RoarPyActor's observations: a wrapper that shows other sensors
    observes those, with its own last observation."""

    class SpeedOnly(rpi.RoarPyActorWrapper):
        def get_sensors(self):
            return [s for s in self._wrapped_object.get_sensors() if s.name == "speed"]

    vehicle = FakeVehicle()
    wrapper = SpeedOnly(vehicle)
    assert list(asyncio.run(wrapper.receive_observation())) == ["speed"]
    assert list(wrapper.get_gym_observation_spec().keys()) == ["speed"]
    assert list(wrapper.get_last_gym_observation()) == ["speed"] and vehicle.get_last_observation() is None
