"""roar_py_interface without ROS: spaces, waypoints, observations of actors and wrappers, action checks."""
import asyncio
import collections

import numpy as np
import pytest

import roar_py_interface as rpi
from roar_py_interface import spaces
from roar_py_ros import conversions


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
    unbounded = spaces.Box(low=-np.inf, high=np.inf, shape=(3,))
    assert np.all(np.isfinite(unbounded.sample()))
    image = spaces.Box(low=0, high=255, shape=(4, 5, 3), dtype=np.uint8)
    sample = image.sample()
    assert sample.dtype == np.uint8 and image.contains(sample)
    assert not image.contains(sample.astype(np.float64)), "float64 cannot be cast to uint8 safely"


def test_discrete_multibinary_and_dict():
    gear = spaces.Discrete(6, start=1)
    gear.seed(0)
    draws = {int(gear.sample()) for _ in range(200)}
    assert draws == {1, 2, 3, 4, 5, 6}
    assert gear.contains(1) and gear.contains(6) and not gear.contains(0) and not gear.contains(7)
    bits = spaces.MultiBinary(3)
    assert bits.contains(np.array([0, 1, 1])) and not bits.contains(np.array([0, 2, 1]))
    d = spaces.Dict({"b": bits, "a": gear})
    assert list(d.keys()) == ["a", "b"], "a plain dict's keys are sorted"
    ordered = spaces.Dict(collections.OrderedDict([("b", bits), ("a", gear)]))
    assert list(ordered.keys()) == ["b", "a"]
    sample = d.sample()
    assert d.contains(sample)
    assert not d.contains({"a": 1}), "a missing key"
    assert d["a"] is gear and len(d) == 2


def test_vehicle_action_spec_is_roar_pys():
    spec = rpi.vehicle_action_spec(auto_gear=True)
    assert list(spec.keys()) == ["throttle", "steer", "brake", "hand_brake", "reverse"]
    assert spec["steer"].low.tolist() == [-1.0] and spec["steer"].high.tolist() == [1.0]
    manual = rpi.vehicle_action_spec(auto_gear=False, num_gears=5)
    assert manual["target_gear"].start == 1 and manual["target_gear"].n == 5
    assert spec.contains(spec.sample())


def test_actions_are_checked_and_steer_turns_to_roar_sims_sign():
    spec = rpi.vehicle_action_spec(auto_gear=False, num_gears=6)
    action = {"throttle": np.array([0.4]), "steer": np.array([0.25]), "brake": 0.0, "hand_brake": np.array([0]),
              "reverse": 0, "target_gear": 3}
    control = conversions.to_vehicle_control(conversions.check_action(action, spec), auto_gear=False)
    assert control.steer == pytest.approx(-0.25), "ROAR_PY's steer is positive right, roar_sim's positive left"
    assert control.throttle == pytest.approx(0.4) and control.manual_gear_shift and control.gear == 3
    with pytest.raises(ValueError, match="'throttle' = 1.5 is outside"):
        conversions.check_action({**action, "throttle": 1.5}, spec)
    with pytest.raises(ValueError, match="'steer' must be one finite number"):
        conversions.check_action({**action, "steer": float("nan")}, spec)
    with pytest.raises(ValueError, match="'brake' is missing"):
        conversions.check_action({k: v for k, v in action.items() if k != "brake"}, spec)
    with pytest.raises(ValueError, match=r"unknown action field\(s\) \['steering'\]"):
        conversions.check_action({**action, "steering": 0.0}, spec)
    with pytest.raises(ValueError, match="'target_gear' = 7.0 is outside"):
        conversions.check_action({**action, "target_gear": 7}, spec)


def test_waypoint_line_representation_round_trips(tmp_path):
    w = rpi.RoarPyWaypoint(np.array([10.0, 5.0, 0.0]), np.array([0.0, 0.0, np.pi / 2]), 12.0)
    left, right = w.line_representation
    assert np.allclose(left, [4.0, 5.0, 0.0]) and np.allclose(right, [16.0, 5.0, 0.0]), "left of a car heading +y is -x"
    back = rpi.RoarPyWaypoint.from_line_representation(left, right, w.roll_pitch_yaw)
    assert np.allclose(back.location, w.location) and back.lane_width == pytest.approx(12.0)
    other = rpi.RoarPyWaypoint(np.array([10.0, 15.0, 0.0]), np.array([0.0, 0.0, -np.pi + 0.1]), 10.0)
    mid = w.interpolate(other, 0.5)
    assert np.allclose(mid.location, [10.0, 10.0, 0.0]) and mid.lane_width == pytest.approx(11.0)
    # from +90 deg to -179.3 deg the short way is through 180: halfway is 135.4 deg
    assert mid.roll_pitch_yaw[2] == pytest.approx(rpi.normalize_rad(np.pi / 2 + rpi.normalize_rad(-np.pi + 0.1 - np.pi / 2) / 2))
    assert mid.roll_pitch_yaw[2] > np.pi / 2
    dense = rpi.interpolate_waypoints([w, other], 1.0, closed=False)
    assert len(dense) == 10 and np.allclose(dense[3].location, [10.0, 8.0, 0.0])
    path = tmp_path / "w.npz"
    np.savez_compressed(path, **rpi.RoarPyWaypoint.save_waypoint_list([w, other]))
    loaded = rpi.RoarPyWaypoint.load_waypoint_list(np.load(path))
    assert np.allclose(loaded[1].location, other.location) and loaded[1].lane_width == 10.0
    with pytest.raises(KeyError, match="no 'lane_widths'"):
        rpi.RoarPyWaypoint.load_waypoint_list({"locations": np.zeros((1, 3)), "rotations": np.zeros((1, 3))})


def test_interpolation_takes_the_short_way_round():
    a = rpi.RoarPyWaypoint(np.zeros(3), np.array([0.0, 0.0, np.pi - 0.1]), 10.0)
    b = rpi.RoarPyWaypoint(np.ones(3), np.array([0.0, 0.0, -np.pi + 0.1]), 10.0)
    assert abs(abs(a.interpolate(b, 0.5).roll_pitch_yaw[2]) - np.pi) < 1e-9


class FakeSensor(rpi.RoarPyLocationInWorldSensor):
    def __init__(self, name, value):
        super().__init__(name)
        self.value = value
        self.last = None

    async def receive_observation(self):
        self.last = rpi.RoarPyLocationInWorldSensorData(*self.value)
        return self.last

    def get_last_observation(self):
        return self.last

    def close(self):
        pass

    def is_closed(self):
        return False


class FakeVehicle(rpi.RoarPyBaseVehicle):
    def __init__(self):
        super().__init__("fake")
        self.sensors = [FakeSensor("gps", (1, 2, 3)), FakeSensor("gps", (4, 5, 6)), FakeSensor("speed", (0, 0, 0))]
        self.actions = []

    def get_sensors(self):
        return self.sensors

    async def _apply_action(self, action):
        self.actions.append(action)
        return True

    def close(self):
        pass

    def is_closed(self):
        return False


class ForwardingWrapper(rpi.RoarPyActor):
    """Competition code's pattern: its own attributes only (no RoarPyActor.__init__), every call forwarded."""

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
    for actor in (vehicle, ForwardingWrapper(vehicle)):
        assert actor.get_last_observation() is None or isinstance(actor, ForwardingWrapper)
        obs = asyncio.run(actor.receive_observation())
        assert list(obs) == ["gps_1", "gps_2", "speed"]
        gym = actor.convert_obs_to_gym_obs(obs)
        assert np.allclose(gym["gps_2"], [4, 5, 6])
        assert actor.get_gym_observation_spec().contains(gym)
        assert np.allclose(actor.get_last_gym_observation()["gps_1"], [1, 2, 3])
        action = actor.get_action_spec().sample()
        assert asyncio.run(actor.apply_action(action))
    assert len(vehicle.actions) == 2


def test_camera_data_converts_to_images():
    rgb = rpi.RoarPyCameraSensorDataRGB(np.zeros((6, 8, 3), np.uint8))
    assert rgb.get_size() == (8, 6) and rgb.get_image().size == (8, 6)
    grey = rpi.RoarPyCameraSensorDataGreyscale.from_image(rgb.get_image())
    assert grey.to_gym().shape == (6, 8, 1)
    depth = rpi.RoarPyCameraSensorDataDepth(np.full((6, 8, 1), np.inf, np.float32))
    assert depth.get_image().mode == "F"
    ss = rpi.RoarPyCameraSensorDataSemanticSegmentation(np.ones((6, 8, 1), np.uint64))
    assert tuple(np.asarray(ss.get_image())[0, 0]) == tuple(rpi.SEMANTIC_LABEL_COLOR_MAP[1][0])
    lidar = rpi.RoarPyLiDARSensorData(np.ones((3, 4), np.float32), 32, 0.0, max_points=5)
    assert lidar.convert_obs_to_gym_obs().shape == (5, 4) and lidar.to_gym()[3:].sum() == 0
