"""roar_rl: roar_ros's racing environment from Python, in process and vectorised (C++ underneath, no ROS).

    import roar_rl
    envs = roar_rl.VectorEnv("roar_sprint", "state", num_envs=8, num_threads=2)
    obs, infos = envs.reset(seed=0)
    obs, rewards, terminations, truncations, infos = envs.step(envs.action_space.sample())
"""
from .vector_env import VectorEnv, available_env_options, available_maps, batch_space  # noqa: F401
