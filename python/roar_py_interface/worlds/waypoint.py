"""ROAR_PY's waypoints: the centre of the road, its orientation and width, and the tracker that follows a
point along a closed list of them (ROAR_PY_RL measures progress with it)."""
import bisect
import collections
import dataclasses
import functools
import math
import typing

import numpy as np

from ..transforms import euler2mat, normalize_rad

__all__ = ["RoarPyWaypoint", "RoarPyWaypointsProjection", "RoarPyWaypointsTracker", "normalize_rad", "euler2mat"]


def _point_segment_distances(point: np.ndarray, starts: np.ndarray, ends: np.ndarray) -> np.ndarray:
    edge = ends - starts
    length2 = np.einsum("...i,...i->...", edge, edge)
    t = np.clip(np.einsum("...i,...i->...", point - starts, edge) / np.where(length2 > 0, length2, 1.0), 0.0, 1.0)
    closest = starts + t[..., None] * edge
    return np.linalg.norm(point - closest, axis=-1)


def _quad_distances(quads: np.ndarray, point: np.ndarray) -> np.ndarray:
    """Distance from a 2-D point to each quadrilateral (K x 4 x 2, corners in order): 0 inside (even-odd
    rule, as a shapely Polygon of the same corners measures it), else to the nearest edge."""
    starts, ends = quads, np.roll(quads, -1, axis=1)
    edge_distance = _point_segment_distances(point, starts, ends).min(axis=1)
    y0, y1 = starts[..., 1], ends[..., 1]
    crosses = (y0 > point[1]) != (y1 > point[1])
    with np.errstate(divide="ignore", invalid="ignore"):
        x_at = starts[..., 0] + (point[1] - y0) * (ends[..., 0] - starts[..., 0]) / (y1 - y0)
    inside = (np.count_nonzero(crosses & (point[0] < x_at), axis=1) % 2) == 1
    return np.where(inside, 0.0, edge_distance)


@dataclasses.dataclass(eq=False)
class RoarPyWaypoint:
    location: np.ndarray        # x, y, z of the centre of the road, m
    roll_pitch_yaw: np.ndarray  # the road's orientation, rad: a car along the road has the same
    lane_width: float           # the road's width here, m

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, RoarPyWaypoint):
            return False
        return (np.allclose(self.location, other.location) and np.allclose(self.roll_pitch_yaw, other.roll_pitch_yaw)
                and np.allclose(self.lane_width, other.lane_width))

    @functools.cached_property
    def line_representation(self) -> typing.Tuple[np.ndarray, np.ndarray]:
        """The road's two edges: (left, right) of the direction of travel."""
        half = euler2mat(*self.roll_pitch_yaw).dot(np.array([0.0, self.lane_width / 2.0, 0.0]))
        return self.location + half, self.location - half

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

    @staticmethod
    def from_line_representation(point_1: np.ndarray, point_2: np.ndarray,
                                 roll_pitch_yaw: np.ndarray) -> "RoarPyWaypoint":
        point_1, point_2 = np.asarray(point_1), np.asarray(point_2)
        return RoarPyWaypoint((point_1 + point_2) / 2, roll_pitch_yaw, float(np.linalg.norm(point_1 - point_2)))

    @staticmethod
    def interpolate(point_1: "RoarPyWaypoint", point_2: "RoarPyWaypoint", alpha: float) -> "RoarPyWaypoint":
        """ROAR_PY's blend: point_1 weighted alpha and point_2 weighted 1 - alpha (angles blended as numbers,
        then wrapped), so alpha = 1 gives point_1."""
        location = point_1.location * alpha + point_2.location * (1 - alpha)
        roll_pitch_yaw = normalize_rad(point_1.roll_pitch_yaw * alpha + point_2.roll_pitch_yaw * (1 - alpha))
        lane_width = point_1.lane_width * alpha + point_2.lane_width * (1 - alpha)
        return RoarPyWaypoint(location, roll_pitch_yaw, lane_width)

    @staticmethod
    def distance_to_waypoint_polygon(waypoint1: "RoarPyWaypoint", waypoint2: "RoarPyWaypoint", point) -> float:
        """Distance (m, in the ground plane) from a point to the stretch of road between two waypoints."""
        p1, p2 = waypoint1.line_representation
        p3, p4 = waypoint2.line_representation
        quad = np.array([[p1[:2], p2[:2], p4[:2], p3[:2]]])
        return float(_quad_distances(quad, np.asarray(point, dtype=np.float64)[:2])[0])


RoarPyWaypointsProjection = collections.namedtuple("RoarPyWaypointsProjectResult",
                                                   ["waypoint_idx", "distance_from_waypoint"])


class RoarPyWaypointsTracker:
    """A closed list of waypoints with the distance along it: traces points onto it and moves along it."""

    _FIRST_WINDOW = 8  # steps either way searched before the whole loop (the answer is the same)

    def __init__(self, waypoints: typing.List[RoarPyWaypoint], current_traced_index: int = 0):
        if len(waypoints) <= 1:
            raise ValueError(f"RoarPyWaypointsTracker: needs at least 2 waypoints, got {len(waypoints)}")
        self.current_traced_index = current_traced_index
        self.waypoints = waypoints

    @property
    def waypoints(self) -> typing.List[RoarPyWaypoint]:
        return self._waypoints

    @waypoints.setter
    def waypoints(self, waypoints: typing.List[RoarPyWaypoint]):
        if len(waypoints) <= 1:
            raise ValueError(f"RoarPyWaypointsTracker: needs at least 2 waypoints, got {len(waypoints)}")
        self._waypoints = waypoints
        self._rebuild_waypoints_distances()

    def _rebuild_waypoints_distances(self) -> None:
        locations = np.array([w.location for w in self._waypoints], dtype=np.float64)
        self._distance_between_waypoints = np.linalg.norm(np.roll(locations, -1, axis=0) - locations, axis=1).tolist()
        cumulative = np.concatenate([[0.0], np.cumsum(self._distance_between_waypoints)])
        self._total_distance_from_first_waypoint = cumulative[:-1].tolist()
        self._total_distance = float(cumulative[-1])
        edges = np.array([w.line_representation for w in self._waypoints])[:, :, :2]  # N x (left, right) x 2
        following = np.roll(edges, -1, axis=0)
        # The road between waypoint i and i + 1 as ROAR_PY's polygon: left_i, right_i, right_i+1, left_i+1.
        self._quads = np.stack([edges[:, 0], edges[:, 1], following[:, 1], following[:, 0]], axis=1)

    def _search_order(self, start_idx: int, steps: int) -> np.ndarray:
        """Segment indices in ROAR_PY's search order: forward i - 1, backward i, for i = 1, 2, ..."""
        count = len(self._waypoints)
        i = np.arange(1, steps + 1)
        order = np.empty(2 * steps, dtype=np.int64)
        order[0::2] = (start_idx + i - 1) % count
        order[1::2] = (start_idx - i) % count
        return order

    def _closest_segment(self, point_2d: np.ndarray, start_idx: int) -> int:
        """ROAR_PY's answer: the first segment, in search order, at the least distance (a search that stops at
        the first one the point lies on)."""
        steps = int(math.ceil(len(self._waypoints) / 2)) + 1
        window = self._search_order(start_idx, min(steps, self._FIRST_WINDOW))
        distances = _quad_distances(self._quads[window], point_2d)
        hit = np.flatnonzero(distances == 0.0)
        if len(hit):
            return int(window[hit[0]])
        order = self._search_order(start_idx, steps)
        distances = _quad_distances(self._quads[order], point_2d)
        return int(order[np.argmin(distances)])

    def trace_point(self, point: np.ndarray, start_idx: int = 0) -> RoarPyWaypointsProjection:
        """The segment the point lies on (or nearest it), searched outwards from start_idx, and how far along
        that segment's direction the point is from its first waypoint (m)."""
        point = np.asarray(point, dtype=np.float64)
        index = self._closest_segment(point[:2], int(start_idx))
        following = self._waypoints[(index + 1) % len(self._waypoints)]
        delta = following.location - self._waypoints[index].location
        projected = float(np.dot(delta, point - self._waypoints[index].location)) / self._distance_between_waypoints[index]
        return RoarPyWaypointsProjection(index, projected)

    def trace_forward_projection(self, projection: RoarPyWaypointsProjection,
                                 distance: float) -> RoarPyWaypointsProjection:
        """The projection distance metres further along the waypoints (ROAR_PY takes the distance modulo
        the lap, so a negative one goes forward by the lap less its size)."""
        count = len(self._waypoints)
        remaining = distance % self._total_distance
        index, along = projection.waypoint_idx, projection.distance_from_waypoint
        if remaining <= 0:
            return RoarPyWaypointsProjection(index, along)
        # ROAR_PY walks the segments one by one; the same walk as a search of the distances along the lap:
        # the rest of this segment first, then the segment holding the point (test_roar_py_interface
        # test_forward_projections_walk_as_roar_pys).
        to_progress = self._distance_between_waypoints[index] - along
        if remaining < to_progress:
            return RoarPyWaypointsProjection(index, along + remaining)
        remaining -= to_progress
        index = (index + 1) % count
        at = self._total_distance_from_first_waypoint[index] + remaining
        if at >= self._total_distance:
            at -= self._total_distance
        found = bisect.bisect_right(self._total_distance_from_first_waypoint, at) - 1
        return RoarPyWaypointsProjection(found, at - self._total_distance_from_first_waypoint[found])

    def delta_distance_projection(self, projection_origin: RoarPyWaypointsProjection,
                                  projection_destination: RoarPyWaypointsProjection) -> float:
        """Signed distance along the lap from origin to destination, the shorter way (m)."""
        origin = self.total_distance_from_first_waypoint(projection_origin)
        destination = self.total_distance_from_first_waypoint(projection_destination)
        delta = (destination - origin + self._total_distance) % self._total_distance
        if delta > self._total_distance / 2:
            delta -= self._total_distance
        return delta

    def get_interpolated_waypoint(self, projection: RoarPyWaypointsProjection) -> RoarPyWaypoint:
        """The waypoint at a projection, blended with ROAR_PY's RoarPyWaypoint.interpolate(previous, next,
        share along): as in ROAR_PY, its weights give the next waypoint at the start of a segment."""
        previous = self._waypoints[projection.waypoint_idx]
        following = self._waypoints[(projection.waypoint_idx + 1) % len(self._waypoints)]
        alpha = min(max(projection.distance_from_waypoint / self._distance_between_waypoints[projection.waypoint_idx],
                        0.0), 1.0)
        return RoarPyWaypoint.interpolate(previous, following, alpha)

    def total_distance_from_first_waypoint(self, projection_result: RoarPyWaypointsProjection) -> float:
        return self._total_distance_from_first_waypoint[projection_result.waypoint_idx] + \
            projection_result.distance_from_waypoint
