"""ROAR_PY's occupancy-map producer: the road drawn from waypoints around a place, the car's forward up."""
import typing

import numpy as np
from PIL import Image, ImageDraw

from .waypoint import RoarPyWaypoint


def line_intersects_line(line1_start: np.ndarray, line1_end: np.ndarray, line2_start: np.ndarray,
                         line2_end: np.ndarray) -> bool:
    """Whether two 2-D segments cross (parallel ones never do), ROAR_PY's test."""
    return bool(_segments_cross(np.asarray(line1_start, np.float64), np.asarray(line1_end, np.float64),
                                np.asarray(line2_start, np.float64), np.asarray(line2_end, np.float64)))


def _segments_cross(line1_start: np.ndarray, line1_end: np.ndarray, line2_start: np.ndarray,
                    line2_end: np.ndarray) -> np.ndarray:
    """line_intersects_line over arrays of segments (..., 2), the same arithmetic in the same order."""
    line1_diff = line1_end - line1_start
    line2_diff = line2_end - line2_start
    d = line1_diff[..., 0] * line2_diff[..., 1] - line1_diff[..., 1] * line2_diff[..., 0]
    parallel = d == 0
    d = np.where(parallel, 1.0, d)  # parallel segments never cross: their quotients are not looked at
    r = ((line1_start[..., 1] - line2_start[..., 1]) * line2_diff[..., 0]
         - (line1_start[..., 0] - line2_start[..., 0]) * line2_diff[..., 1]) / d
    s = ((line1_start[..., 1] - line2_start[..., 1]) * line1_diff[..., 0]
         - (line1_start[..., 0] - line2_start[..., 0]) * line1_diff[..., 1]) / d
    return ~parallel & (0 <= r) & (r <= 1) & (0 <= s) & (s <= 1)


class RoarPyOccupancyMapProducer:
    """Draws the road (255) around a place on a width x height image covering width_world x height_world
    metres, centred on the place and turned so that the given yaw points up."""

    def __init__(self, waypoints: typing.List[RoarPyWaypoint], width: int, height: int, width_world: float,
                 height_world: float):
        self.image = Image.new("L", (width, height), 0)
        self.width_world = width_world
        self.height_world = height_world
        self.waypoints = waypoints
        self.start_index = -1
        self._edges: typing.Optional[np.ndarray] = None
        self._edges_of: typing.Optional[typing.List[RoarPyWaypoint]] = None

    def _cross_sections(self) -> np.ndarray:
        """(N, 2, 2): each waypoint's road edges (x, y), kept while the list of waypoints is the same."""
        if self._edges is None or self._edges_of is not self.waypoints or len(self._edges) != len(self.waypoints):
            self._edges = np.array([[w.line_representation[0][:2], w.line_representation[1][:2]]
                                    for w in self.waypoints], dtype=np.float64).reshape(-1, 2, 2)
            self._edges_of = self.waypoints
            self._low, self._high = self._edges.min(axis=1), self._edges.max(axis=1)
        return self._edges

    @property
    def width(self) -> int:
        return self.image.width

    @width.setter
    def width(self, value: int):
        self.image = self.image.resize((value, self.height))

    @property
    def height(self) -> int:
        return self.image.height

    @height.setter
    def height(self, value: int):
        self.image = self.image.resize((self.width, value))

    def _in_range_of(self, indices: np.ndarray, location_min: np.ndarray, location_max: np.ndarray) -> np.ndarray:
        """_in_range of the waypoints at these indices at once (the drawing's cost: the runner's map asks it each
        tick)."""
        edges = self._cross_sections()
        side_1 = np.array([location_min[0], location_max[1]])
        side_2 = np.array([location_max[0], location_min[1]])
        crossed = np.zeros(len(indices), dtype=bool)
        # Only a cross-section whose box meets the square can cross its sides.
        low, high = self._low[indices], self._high[indices]
        near = np.flatnonzero((low[:, 0] <= location_max[0]) & (low[:, 1] <= location_max[1]) &
                              (high[:, 0] >= location_min[0]) & (high[:, 1] >= location_min[1]))
        if len(near) == 0:
            return crossed
        # The square's four sides against every near cross-section: (near, 4).
        sides_from = np.array([location_min, side_1, location_max, side_2])
        sides_to = np.array([side_1, location_max, side_2, location_min])
        ends = edges[indices[near]]
        crossed[near] = _segments_cross(ends[:, 0][:, None], ends[:, 1][:, None], sides_from[None],
                                        sides_to[None]).any(axis=1)
        return crossed

    def _pairs_in_range(self, location_min, location_max) -> typing.List[typing.Tuple[RoarPyWaypoint, RoarPyWaypoint]]:
        # ROAR_PY's walk: from ten before the last start, the first waypoint in range, then the run of those
        # after it in range, paired (the same pairs as its loop, test_roar_py_interface
        # test_the_occupancy_map_draws_what_roar_pys_loop_draws). The waypoints are looked at a stretch at a
        # time, the first stretch where the last map was.
        count = len(self.waypoints)
        if count == 0:
            return []
        location_min = np.asarray(location_min, np.float64)
        location_max = np.asarray(location_max, np.float64)
        search_from = 0 if self.start_index == -1 else self.start_index - 10
        stretch = min(count, 256)
        first = None
        for begin in range(0, count, stretch):
            order = (search_from + np.arange(begin, min(begin + stretch, count))) % count
            hits = np.flatnonzero(self._in_range_of(order, location_min, location_max))
            if len(hits):
                first = int(order[hits[0]])
                break
        last = None
        if first is not None:
            self.start_index = first
            last = self.waypoints[first]
        pairs = []
        for begin in range(1, count + 1, stretch):
            order = (self.start_index + np.arange(begin, min(begin + stretch, count + 1))) % count
            in_range = self._in_range_of(order, location_min, location_max)
            for index, inside in zip(order.tolist(), in_range.tolist()):
                waypoint = self.waypoints[index]
                if last is not None:
                    pairs.append((last, waypoint))
                    last = None
                if inside:
                    last = waypoint
                else:
                    return pairs
        return pairs

    def plot_occupancy_map(self, location_2d: np.ndarray, rotation_yaw: float) -> Image.Image:
        """The occupancy map around location_2d (x, y), rotation_yaw up."""
        location_2d = np.asarray(location_2d, dtype=np.float64)
        if location_2d.shape != (2,):
            raise ValueError(f"plot_occupancy_map: location_2d must be [x, y], got shape {location_2d.shape}")
        half = np.array([self.width_world, self.height_world])  # twice the image's reach: room to rotate
        draw = ImageDraw.Draw(self.image)
        pairs = self._pairs_in_range(location_2d - half, location_2d + half)
        if pairs:
            # Each pair's quadrilateral (first's left and right edge, second's right and left), all at once.
            corners = np.array([[first.line_representation[0][:2], first.line_representation[1][:2],
                                 second.line_representation[1][:2], second.line_representation[0][:2]]
                                for first, second in pairs], dtype=np.float64)
            for quad in self._pixels_of(corners.reshape(-1, 2), rotation_yaw, location_2d).reshape(-1, 4, 2):
                draw.polygon([tuple(point) for point in quad.tolist()], fill=255)
        drawn = self.image
        self.image = Image.new("L", drawn.size, 0)
        return drawn

    def world_to_pixel(self, location_2d: np.ndarray, rotation_center: float,
                       center_2d: np.ndarray) -> typing.Tuple[float, float]:
        """Pixel (column, row) of a world point on the map centred on center_2d with rotation_center up."""
        column, row = self._pixels_of(np.asarray(location_2d, np.float64).reshape(1, 2), rotation_center,
                                      center_2d)[0]
        return (float(column), float(row))

    def _pixels_of(self, points: np.ndarray, rotation_center: float, center_2d: np.ndarray) -> np.ndarray:
        """world_to_pixel of (N, 2) points: (N, 2) columns and rows."""
        local = points - np.asarray(center_2d, np.float64)
        cos_r, sin_r = np.cos(rotation_center), np.sin(rotation_center)
        local = local @ np.array([[cos_r, sin_r], [-sin_r, cos_r]]).T
        local = local * np.array([self.height / self.height_world, self.width / self.width_world])
        return np.column_stack([-local[:, 1] + self.width / 2, -local[:, 0] + self.height / 2])
