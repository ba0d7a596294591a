"""ROAR_PY's waypoint: the centre of the road, the road's orientation and its width."""
import typing

import numpy as np


def euler2mat(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """Rz(yaw) Ry(pitch) Rx(roll): transforms3d's euler2mat with its default static xyz axes."""
    cr, sr, cp, sp, cy, sy = np.cos(roll), np.sin(roll), np.cos(pitch), np.sin(pitch), np.cos(yaw), np.sin(yaw)
    return np.array([
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ])


def normalize_rad(rad):
    return (rad + np.pi) % (2 * np.pi) - np.pi


class RoarPyWaypoint:
    def __init__(self, location: np.ndarray, roll_pitch_yaw: np.ndarray, lane_width: float):
        self.location = np.asarray(location, dtype=np.float64)
        self.roll_pitch_yaw = np.asarray(roll_pitch_yaw, dtype=np.float64)
        self.lane_width = float(lane_width)

    def __repr__(self):
        return f"RoarPyWaypoint(location={self.location}, roll_pitch_yaw={self.roll_pitch_yaw}, lane_width={self.lane_width})"

    @property
    def line_representation(self) -> typing.Tuple[np.ndarray, np.ndarray]:
        """The road's two edges: (left, right) of the direction of travel."""
        half = euler2mat(*self.roll_pitch_yaw) @ np.array([0.0, self.lane_width / 2.0, 0.0])
        return self.location + half, self.location - half

    @staticmethod
    def from_line_representation(point1: np.ndarray, point2: np.ndarray,
                                 roll_pitch_yaw: np.ndarray) -> "RoarPyWaypoint":
        point1, point2 = np.asarray(point1, np.float64), np.asarray(point2, np.float64)
        return RoarPyWaypoint((point1 + point2) / 2.0, roll_pitch_yaw, float(np.linalg.norm(point1 - point2)))

    def interpolate(self, other: "RoarPyWaypoint", t: float) -> "RoarPyWaypoint":
        """The waypoint a share t of the way to other (angles along the shorter way round)."""
        rpy = self.roll_pitch_yaw + t * normalize_rad(other.roll_pitch_yaw - self.roll_pitch_yaw)
        return RoarPyWaypoint(self.location + t * (other.location - self.location), normalize_rad(rpy),
                              self.lane_width + t * (other.lane_width - self.lane_width))

    @staticmethod
    def load_waypoint_list(waypoint_dict: typing.Mapping[str, np.ndarray]) -> typing.List["RoarPyWaypoint"]:
        for key in ("locations", "rotations", "lane_widths"):
            if key not in waypoint_dict:
                raise KeyError(f"load_waypoint_list: the waypoint file has no '{key}' array "
                               f"(it has {sorted(waypoint_dict.keys())})")
        widths = np.asarray(waypoint_dict["lane_widths"]).flatten()
        return [RoarPyWaypoint(waypoint_dict["locations"][i], waypoint_dict["rotations"][i], widths[i])
                for i in range(len(waypoint_dict["locations"]))]

    @staticmethod
    def save_waypoint_list(waypoints: typing.Sequence["RoarPyWaypoint"]) -> typing.Dict[str, np.ndarray]:
        return {
            "locations": np.stack([w.location for w in waypoints], axis=0),
            "rotations": np.stack([w.roll_pitch_yaw for w in waypoints], axis=0),
            "lane_widths": np.stack([w.lane_width for w in waypoints], axis=0),
        }


def interpolate_waypoints(waypoints: typing.Sequence[RoarPyWaypoint], spacing: float,
                          closed: bool = True) -> typing.List[RoarPyWaypoint]:
    """Waypoints every `spacing` metres along the polyline through `waypoints`."""
    if spacing <= 0:
        raise ValueError(f"interpolate_waypoints: spacing must be positive, got {spacing}")
    pairs = list(zip(waypoints, list(waypoints[1:]) + ([waypoints[0]] if closed else [])))
    out = []
    carry = 0.0
    for a, b in pairs:
        length = float(np.linalg.norm(b.location - a.location))
        s = carry
        while s < length:
            out.append(a.interpolate(b, s / length))
            s += spacing
        carry = s - length
    return out
