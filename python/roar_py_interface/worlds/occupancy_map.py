"""ROAR_PY's occupancy-map producer: the road drawn from waypoints around a place, the car's forward up."""
import typing

import numpy as np
from PIL import Image, ImageDraw

from .waypoint import RoarPyWaypoint


def line_intersects_line(line1_start: np.ndarray, line1_end: np.ndarray, line2_start: np.ndarray,
                         line2_end: np.ndarray) -> bool:
    """Whether two 2-D segments cross (parallel ones never do), ROAR_PY's test."""
    line1_diff = line1_end - line1_start
    line2_diff = line2_end - line2_start
    d = line1_diff[0] * line2_diff[1] - line1_diff[1] * line2_diff[0]
    if d == 0:
        return False
    r = ((line1_start[1] - line2_start[1]) * line2_diff[0] - (line1_start[0] - line2_start[0]) * line2_diff[1]) / d
    s = ((line1_start[1] - line2_start[1]) * line1_diff[0] - (line1_start[0] - line2_start[0]) * line1_diff[1]) / d
    return 0 <= r <= 1 and 0 <= s <= 1


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

    def _in_range(self, waypoint: RoarPyWaypoint, location_min: np.ndarray, location_max: np.ndarray) -> bool:
        """Whether the waypoint's cross-section crosses the square around the place (ROAR_PY's test)."""
        start, end = waypoint.line_representation[0][:2], waypoint.line_representation[1][:2]
        side_1 = np.array([location_min[0], location_max[1]])
        side_2 = np.array([location_max[0], location_min[1]])
        return any(line_intersects_line(start, end, a, b) for a, b in
                   ((location_min, side_1), (side_1, location_max), (location_max, side_2), (side_2, location_min)))

    def _pairs_in_range(self, location_min, location_max) -> typing.List[typing.Tuple[RoarPyWaypoint, RoarPyWaypoint]]:
        count = len(self.waypoints)
        last = None
        search_from = 0 if self.start_index == -1 else self.start_index - 10
        for i in range(count):
            index = (search_from + i) % count
            if self._in_range(self.waypoints[index], location_min, location_max):
                self.start_index, last = index, self.waypoints[index]
                break
        pairs = []
        for i in range(1, count + 1):
            waypoint = self.waypoints[(self.start_index + i) % count]
            if last is not None:
                pairs.append((last, waypoint))
                last = None
            if self._in_range(waypoint, location_min, location_max):
                last = waypoint
            else:
                break
        return pairs

    def plot_occupancy_map(self, location_2d: np.ndarray, rotation_yaw: float) -> Image.Image:
        """The occupancy map around location_2d (x, y), rotation_yaw up."""
        location_2d = np.asarray(location_2d, dtype=np.float64)
        if location_2d.shape != (2,):
            raise ValueError(f"plot_occupancy_map: location_2d must be [x, y], got shape {location_2d.shape}")
        half = np.array([self.width_world, self.height_world])  # twice the image's reach: room to rotate
        draw = ImageDraw.Draw(self.image)
        for first, second in self._pairs_in_range(location_2d - half, location_2d + half):
            draw.polygon([
                self.world_to_pixel(first.line_representation[0][:2], rotation_yaw, location_2d),
                self.world_to_pixel(first.line_representation[1][:2], rotation_yaw, location_2d),
                self.world_to_pixel(second.line_representation[1][:2], rotation_yaw, location_2d),
                self.world_to_pixel(second.line_representation[0][:2], rotation_yaw, location_2d),
            ], fill=255)
        drawn = self.image
        self.image = Image.new("L", drawn.size, 0)
        return drawn

    def world_to_pixel(self, location_2d: np.ndarray, rotation_center: float,
                       center_2d: np.ndarray) -> typing.Tuple[float, float]:
        """Pixel (column, row) of a world point on the map centred on center_2d with rotation_center up."""
        local = np.asarray(location_2d) - np.asarray(center_2d)
        cos_r, sin_r = np.cos(rotation_center), np.sin(rotation_center)
        local = np.array([[cos_r, sin_r], [-sin_r, cos_r]]) @ local
        local = local * np.array([self.height / self.height_world, self.width / self.width_world])
        return (-local[1] + self.width / 2, -local[0] + self.height / 2)
