"""ROAR_PY's visualizations."""
from .visualizer import RoarPyVisualizer  # noqa: F401
