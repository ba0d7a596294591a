#!/usr/bin/env python3
"""Steps per second of roar_rl.VectorEnv from Python, against the C++ VectorEnv (roar_bench's RlEnvSteps,
run here in the same session) and against N single-thread processes, for 1..N threads: the environment
roar_bench times (Roar Sprint, config/rl/state.yaml, or that plus an 84x84 RGB camera; the car chases the
waypoint 10 m ahead; one environment on one thread, --envs-per-thread a thread beyond, two by default: the
C++ figure, roar_bench's two a thread, is compared only then and at one thread, where both step one
environment; printed nan otherwise).
The synchronous Python figure is given twice: the whole loop, and the module's step alone (the agent's numpy
chase timed and taken out).

    /usr/bin/python3 bench/roar_rl_bench.py [--seconds S] [--max-threads N] [--repeats R] [--envs-per-thread E]
"""
import argparse
import multiprocessing
import os
import re
import subprocess
import tempfile
import time

import numpy as np

import roar_paths
import roar_rl

ROOT = roar_paths.package_root()


def options_file(camera: bool) -> str:
    state = roar_paths.layout()["rl"] / "state.yaml"
    text = state.read_text()
    if not camera:
        return str(state)
    text = text.replace("  waypoint_distances:", "  camera: {width: 84, height: 84, rgb: true}\n  waypoint_distances:")
    handle = tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False)
    handle.write(text)
    handle.close()
    return handle.name


def chase(obs, action):
    """roar_bench's chase action, written into `action` (arrays made once, as an agent's would be; ufuncs
    rather than np.clip, which took 5 us of the 10 us this took on one environment's 1x1 array)."""
    wp = obs["waypoints_information"]["waypoint_10"]
    steer = action["steer"]
    np.arctan2(wp[:, 1:2], wp[:, 0:1], out=steer)
    np.multiply(steer, 1.5, out=steer)
    np.minimum(steer, 1.0, out=steer)
    np.maximum(steer, -1.0, out=steer)
    return action


def zero_action(n):
    return {"throttle": np.full((n, 1), 0.6), "steer": np.zeros((n, 1)), "brake": np.zeros((n, 1)),
            "hand_brake": np.zeros((n, 1)), "reverse": np.zeros((n, 1))}


def python_rates(options: str, num_envs: int, threads: int, seconds: float):
    """Steps/s of the loop (the agent's numpy chase included), and of the module's step alone (the time spent
    in the chase taken out: what the C++ figure's own chase, a few arithmetic operations, hardly costs)."""
    envs = roar_rl.VectorEnv("roar_sprint", options, num_envs=num_envs, num_threads=threads)
    obs, _ = envs.reset(seed=1)
    action = zero_action(num_envs)
    for _ in range(20):
        obs, *_ = envs.step(chase(obs, action))
    steps, agent, started = 0, 0.0, time.perf_counter()
    while time.perf_counter() - started < seconds:
        before = time.perf_counter()
        act = chase(obs, action)
        agent += time.perf_counter() - before
        obs, *_ = envs.step(act)
        steps += 1
    elapsed = time.perf_counter() - started
    return steps * num_envs / elapsed, steps * num_envs / (elapsed - agent)


def python_rate(options: str, num_envs: int, threads: int, seconds: float) -> float:
    return python_rates(options, num_envs, threads, seconds)[0]


def async_rate(options: str, num_envs: int, threads: int, seconds: float) -> float:
    """EnvPool's asynchronous batching: half the environments per recv(), sent back at once."""
    batch = max(1, num_envs // 2)
    envs = roar_rl.VectorEnv("roar_sprint", options, num_envs=num_envs, num_threads=threads, batch_size=batch)
    envs.reset(seed=1)
    envs.send(zero_action(num_envs), np.arange(num_envs))
    action = zero_action(batch)
    steps, started = 0, time.perf_counter()
    while time.perf_counter() - started < seconds:
        obs, _, _, _, infos = envs.recv()
        envs.send(chase(obs, action), np.array(infos["env_id"]))
        steps += batch
    return steps / (time.perf_counter() - started)


def cpp_rate(camera: bool, threads: int, seconds: float) -> float:
    done = subprocess.run([str(ROOT / "devel" / "lib" / "roar_ros" / "roar_bench"),
                           f"--benchmark_filter=RlEnvSteps/camera:{int(camera)}/threads:{threads}/",
                           f"--benchmark_min_time={seconds}"], capture_output=True, text=True, check=True)
    match = re.search(r"steps_per_s=([0-9.]+)(k?)/s", done.stdout)
    if not match:
        raise RuntimeError("roar_bench printed no RlEnvSteps figure:\n" + done.stdout[-2000:])
    return float(match.group(1)) * (1000.0 if match.group(2) else 1.0)


def one_process(args):
    options, num_envs, seconds, queue = args
    queue.put(python_rate(options, num_envs, 1, seconds))


def processes_rate(options: str, count: int, num_envs: int, seconds: float) -> float:
    ctx = multiprocessing.get_context("spawn")
    queue = ctx.Queue()
    procs = [ctx.Process(target=one_process, args=((options, num_envs, seconds, queue),)) for _ in range(count)]
    for p in procs:
        p.start()
    total = sum(queue.get() for _ in procs)
    for p in procs:
        p.join()
    return total


def random_action_share(num_envs: int, seconds: float):
    """A random-action loop (Gymnasium's habit): the time of action_space.sample() and of step(), a call each."""
    envs = roar_rl.VectorEnv("roar_sprint", "state", num_envs=num_envs, num_threads=min(2, num_envs))
    envs.reset(seed=1)
    envs.action_space.seed(0)
    sampling = stepping = 0.0
    calls, started = 0, time.perf_counter()
    while time.perf_counter() - started < seconds:
        before = time.perf_counter()
        action = envs.action_space.sample()
        between = time.perf_counter()
        envs.step(action)
        sampling, stepping, calls = sampling + between - before, stepping + time.perf_counter() - between, calls + 1
    return sampling / calls, stepping / calls


def median(values):
    return sorted(values)[len(values) // 2]


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description="roar_rl.VectorEnv steps/s from Python")
    parser.add_argument("--seconds", type=float, default=3.0)
    parser.add_argument("--max-threads", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--repeats", type=int, default=3,
                        help="rounds of the four measurements, taken in turn; medians are printed")
    parser.add_argument("--envs-per-thread", type=int, default=2,
                        help="environments a thread beyond one thread, in the pools and in each process alike "
                             "(roar_rl_ppo.py trains with 8 environments on 2 threads: 4)")
    args = parser.parse_args()
    if args.envs_per_thread < 1:
        parser.error(f"--envs-per-thread {args.envs_per_thread}: at least 1")
    per_thread = args.envs_per_thread
    sample, step = random_action_share(4, args.seconds)
    print(f"random actions, 4 envs: action_space.sample() {sample * 1e6:.1f} us a call, step() {step * 1e6:.1f} us "
          f"({sample / step:4.2f} of a step; spaces from {'gymnasium' if roar_rl.vector_env.spaces.USING_GYMNASIUM else 'roar_py_interface'})",
          flush=True)
    for camera in (False, True):
        options = options_file(camera)
        name = "camera" if camera else "state"
        for threads in range(1, args.max_threads + 1):
            envs = 1 if threads == 1 else per_thread * threads
            # Asynchronous: per_thread environments a thread, half of them a batch (the caller's Python works on
            # one batch while the other threads step the rest).
            async_envs = per_thread * threads
            # roar_bench's RlEnvSteps steps two environments a thread: the Python / C++ column only for that.
            compared = threads == 1 or per_thread == 2
            rounds = []
            # In turn, round after round, so that a slow spell of the machine falls on all four alike; each
            # ratio is the median of the rounds' own.
            for _ in range(args.repeats):
                cpp = cpp_rate(camera, threads, args.seconds) if compared else float("nan")
                py, module = python_rates(options, envs, threads, args.seconds)
                procs = processes_rate(options, threads, 1 if threads == 1 else per_thread, args.seconds)
                asynchronous = async_rate(options, async_envs, threads, args.seconds)
                rounds.append((cpp, py, procs, asynchronous, module))
            cpp, py, procs, asynchronous, module = (median([r[k] for r in rounds]) for k in range(5))
            py_cpp = median([r[1] / r[0] for r in rounds])
            module_cpp = median([r[4] / r[0] for r in rounds])
            py_procs = median([r[1] / r[2] for r in rounds])
            async_procs = median([r[3] / r[2] for r in rounds])
            print(f"{name:6s} {threads:2d} thread(s) {envs:2d} env(s): Python {py:8.0f} steps/s, C++ {cpp:8.0f} "
                  f"({py_cpp:4.2f}; the module's step alone {module:8.0f}, {module_cpp:4.2f}); {threads} single-thread Python process(es) {procs:8.0f} ({py_procs:4.2f}); "
                  f"asynchronous, {async_envs} envs in batches of {max(1, async_envs // 2)}: {asynchronous:8.0f} "
                  f"({async_procs:4.2f}); medians of {args.repeats} rounds", flush=True)
