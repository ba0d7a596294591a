"""ROAR_PY's visualizer: an actor's last camera frames and occupancy maps as one picture."""
import typing

from PIL import Image

from ..actors import RoarPyActor
from ..sensors import RoarPyCameraSensorData, RoarPyOccupancyMapSensorData


class RoarPyVisualizer:
    """render(): the actor's last observation's images pasted on one canvas as large as the largest, cameras
    from the top left, occupancy maps from the top right (ROAR_PY's layout); None before any observation or
    when it holds no image."""

    def __init__(self, actor: RoarPyActor) -> None:
        self.actor = actor

    def render(self) -> typing.Optional[Image.Image]:
        observation = self.actor.get_last_observation()
        if observation is None:
            return None
        images = []
        for reading in observation.values():
            if isinstance(reading, RoarPyCameraSensorData):
                images.append((reading.get_image(), False))
            elif isinstance(reading, RoarPyOccupancyMapSensorData):
                images.append((reading.occupancy_map, True))
        if not images:
            return None
        width = max(image.size[0] for image, _ in images)
        height = max(image.size[1] for image, _ in images)
        canvas = Image.new("RGB", (width, height))
        for image, from_right in images:
            canvas.paste(image, (width - image.width, 0) if from_right else (0, 0))
        return canvas
