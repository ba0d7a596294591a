"""Rotations in ROAR_PY's conventions (transforms3d's defaults): static xyz Euler angles [roll, pitch, yaw]
in radians, quaternions as (w, x, y, z). The one home of these conversions on the Python side."""
import math

import numpy as np


def euler2mat(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """Rz(yaw) Ry(pitch) Rx(roll): transforms3d.euler.euler2mat with its default static xyz axes."""
    cr, sr, cp, sp, cy, sy = np.cos(roll), np.sin(roll), np.cos(pitch), np.sin(pitch), np.cos(yaw), np.sin(yaw)
    return np.array([
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ])


def euler2quat(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """(w, x, y, z) of static xyz Euler angles: transforms3d.euler.euler2quat."""
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return np.array([cr * cp * cy + sr * sp * sy, sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
                     cr * cp * sy - sr * sp * cy])


def quat2euler(quaternion) -> np.ndarray:
    """[roll, pitch, yaw] of a (w, x, y, z) quaternion (normalised first): transforms3d.euler.quat2euler."""
    w, x, y, z = np.asarray(quaternion, dtype=np.float64) / np.linalg.norm(quaternion)
    roll = math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = math.asin(max(-1.0, min(1.0, 2 * (w * y - z * x))))
    yaw = math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return np.array([roll, pitch, yaw])


def rotate_vector(vector, quaternion) -> np.ndarray:
    """vector rotated by a (w, x, y, z) quaternion: transforms3d.quaternions.rotate_vector."""
    w, x, y, z = np.asarray(quaternion, dtype=np.float64)
    q_vec = np.array([x, y, z])
    v = np.asarray(vector, dtype=np.float64)
    t = 2.0 * np.cross(q_vec, v)
    return v + w * t + np.cross(q_vec, t)


def qinverse(quaternion) -> np.ndarray:
    w, x, y, z = np.asarray(quaternion, dtype=np.float64)
    return np.array([w, -x, -y, -z]) / (w * w + x * x + y * y + z * z)


def normalize_rad(radians):
    return (radians + np.pi) % (2 * np.pi) - np.pi
