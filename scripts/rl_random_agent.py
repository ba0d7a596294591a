#!/usr/bin/python3
"""ROAR_PY's RL loop over ROS, with random actions: read the car's Gymnasium action and observation spaces,
then observe, act, step, and reset when an episode ends.

roar_sim must run in step mode with a car an agent drives (launch/rl.launch: the rl_headless scenario):

    roslaunch roar_ros rl.launch agent:=true steps:=500
    rosrun roar_ros rl_random_agent.py --vehicle agent --steps 500 --seed 0

RoarSimEnv is the environment (reset(seed) -> observation, info; step(action) -> observation, reward,
terminated, truncated, info), the spaces are Gymnasium's in dictionaries (SpaceDescription), and an action
is a dictionary of numpy arrays keyed as ROAR_PY's action spec. The observation holds the car's RL
observation (/<vehicle>/rl/observation) and, like ROAR_PY's sensor readings, the images of its cameras
stamped at the step (/<vehicle>/camera/<name>/image) under camera/<name>.
"""
import argparse
import os
import signal
import sys
import threading
import time

import numpy as np
import rospy
from roar_ros.msg import EpisodeStep, Observation, SpaceDescription, VehicleControl
from roar_ros.srv import ResetEpisode, Step
from sensor_msgs.msg import Image


class Box:
    def __init__(self, entry):
        self.shape = tuple(entry.shape)
        self.dtype = np.dtype(entry.dtype)
        self.low = np.array(entry.low, dtype=np.float64).reshape(self.shape)
        self.high = np.array(entry.high, dtype=np.float64).reshape(self.shape)

    def sample(self, rng):
        low = np.where(np.isfinite(self.low), self.low, -1.0)
        high = np.where(np.isfinite(self.high), self.high, 1.0)
        return rng.uniform(low, high).astype(self.dtype)

    def contains(self, x):
        return x.shape == self.shape and bool(np.all(x >= self.low) and np.all(x <= self.high))


class Discrete:
    def __init__(self, entry):
        self.n, self.start, self.shape = entry.n, entry.start, ()

    def sample(self, rng):
        return np.int64(self.start + rng.integers(self.n))

    def contains(self, x):
        return self.start <= int(x) < self.start + self.n


class MultiBinary:
    def __init__(self, entry):
        self.shape = tuple(entry.shape)

    def sample(self, rng):
        return rng.integers(0, 2, size=self.shape).astype(np.int8)

    def contains(self, x):
        return x.shape == self.shape and bool(np.all((x == 0) | (x == 1)))


def spaces_of(description):
    """A SpaceDescription's leaves as {key: Box | Discrete | MultiBinary}, in flattening order."""
    kinds = {"Box": Box, "Discrete": Discrete, "MultiBinary": MultiBinary}
    return {e.key: kinds[e.type](e) for e in description.entries}


def to_control(action, stamp):
    """ROAR_PY's action (a dict of arrays) as roar_sim's VehicleControl."""
    c = VehicleControl()
    c.header.stamp = stamp
    c.throttle = float(action["throttle"][0])
    c.steer = float(action["steer"][0])
    c.brake = float(action["brake"][0])
    c.hand_brake = bool(action["hand_brake"][0] > 0.5)
    c.reverse = bool(action["reverse"][0])
    if "target_gear" in action:
        c.manual_gear_shift = True
        c.gear = -1 if c.reverse else int(action["target_gear"])
    return c


class RoarSimEnv:
    """A Gymnasium-style environment over roar_sim's RL interface for one agent car."""

    def __init__(self, vehicle="agent", timeout=30.0):
        self.vehicle = vehicle
        self.timeout = timeout
        self._lock = threading.Condition()
        self._observations, self._steps, self._images = {}, {}, {}
        prefix = "/%s/rl/" % vehicle
        self.action_space = spaces_of(rospy.wait_for_message(prefix + "action_space", SpaceDescription, timeout))
        self.observation_space = spaces_of(rospy.wait_for_message(prefix + "observation_space", SpaceDescription, timeout))
        self._subscribers = [
            rospy.Subscriber(prefix + "observation", Observation, self._keep, self._observations, tcp_nodelay=True),
            rospy.Subscriber(prefix + "step", EpisodeStep, self._keep, self._steps, tcp_nodelay=True),
        ]
        # The car's cameras, as ROAR_PY's sensors: every image topic under /<vehicle>/camera/.
        self.cameras = sorted(t.split("/")[3] for t, kind in rospy.get_published_topics("/%s/camera" % vehicle)
                              if kind == "sensor_msgs/Image" and t.endswith("/image"))
        for name in self.cameras:
            self._subscribers.append(rospy.Subscriber("/%s/camera/%s/image" % (vehicle, name), Image, self._keep,
                                                      self._images.setdefault(name, {}), tcp_nodelay=True))
        rospy.wait_for_service("/roar_sim/step", timeout)
        self._step = rospy.ServiceProxy("/roar_sim/step", Step, persistent=True)
        self._reset = rospy.ServiceProxy("/roar_sim/reset_episode", ResetEpisode)
        time.sleep(0.5)  # the subscriptions connect (wall time: simulated time stands still between steps)

    def _keep(self, msg, store):
        with self._lock:
            store[msg.header.stamp] = msg
            self._lock.notify_all()

    def _wait(self, store, stamp, what):
        with self._lock:
            if not self._lock.wait_for(lambda: stamp in store, self.timeout):
                raise RuntimeError("no %s stamped %.3f s arrived" % (what, stamp.to_sec()))
            for old in [s for s in store if s < stamp]:
                del store[old]
            return store[stamp]

    def _observation(self, stamp):
        msg = self._wait(self._observations, stamp, "observation")
        obs = {e.key: np.array(e.data, dtype=np.float64).reshape(self.observation_space[e.key].shape)
               .astype(self.observation_space[e.key].dtype) for e in msg.entries}
        for name in self.cameras:
            image = self._wait(self._images[name], stamp, "image of camera " + name)
            channels = 3 if image.encoding == "rgb8" else 1
            dtype = np.float32 if image.encoding == "32FC1" else np.uint8
            obs["camera/" + name] = np.frombuffer(image.data, dtype=dtype).reshape(image.height, image.width, channels)
        return obs

    def reset(self, seed=None):
        answer = self._reset(vehicle=self.vehicle, seed=-1 if seed is None else seed)
        if not answer.success:
            raise RuntimeError(answer.message)
        return self._observation(answer.stamp), {"stamp": answer.stamp}

    def step(self, action):
        answer = self._step(ticks=1, vehicle_names=[self.vehicle], controls=[to_control(action, rospy.Time(0))])
        if not answer.success:
            raise RuntimeError(answer.message)
        outcome = self._wait(self._steps, answer.stamp, "step outcome")
        info = {k: getattr(outcome, k) for k in ("progress", "track_s", "lateral", "speed", "collision_impulse",
                                                 "laps", "last_lap_time", "episode_steps", "episode_return")}
        info["stamp"] = answer.stamp
        return self._observation(answer.stamp), outcome.reward, outcome.terminated, outcome.truncated, info


def run(steps, vehicle="agent", seed=0, log_every=100):
    """The loop; returns every step's (observation, reward, terminated, truncated, info) and the env."""
    env = RoarSimEnv(vehicle)
    rng = np.random.default_rng(seed)
    observation, info = env.reset(seed=seed)
    history = []
    for i in range(steps):
        action = {key: space.sample(rng) for key, space in env.action_space.items()}
        observation, reward, terminated, truncated, info = env.step(action)
        history.append((observation, reward, terminated, truncated, info))
        if log_every and (i + 1) % log_every == 0:
            rospy.loginfo("rl_random_agent: step %d, t = %.2f s, reward %.3f, episode return %.1f", i + 1,
                          info["stamp"].to_sec(), reward, info["episode_return"])
        if terminated or truncated:
            observation, info = env.reset()
    return history, env


def end_the_launch():
    """Ends the roslaunch that started this node as Ctrl-C would (race_control does the same), so that a run
    that is done is not reported as a required node's death; a parent that is no roslaunch is left alone."""
    parent = os.getppid()
    try:
        with open(f"/proc/{parent}/cmdline", "rb") as f:
            args = f.read().replace(b"\0", b" ").decode(errors="replace")
    except OSError:
        return
    if parent > 1 and "/roslaunch " in args:
        os.kill(parent, signal.SIGINT)
        until = time.monotonic() + 15.0  # wall time: nobody steps the simulated clock any more
        while not rospy.is_shutdown() and time.monotonic() < until:  # roslaunch stops every node, this one too
            time.sleep(0.05)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--vehicle", default="agent")
    parser.add_argument("--steps", type=int, default=1000)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(rospy.myargv(sys.argv)[1:])
    rospy.init_node("rl_random_agent")
    history, _ = run(args.steps, args.vehicle, args.seed)
    rewards = [h[1] for h in history]
    episodes = sum(1 for h in history if h[2] or h[3])
    rospy.loginfo("rl_random_agent: %d steps, %d finished episodes, mean reward %.3f", len(history), episodes,
                  float(np.mean(rewards)) if rewards else 0.0)
    end_the_launch()


if __name__ == "__main__":
    main()
