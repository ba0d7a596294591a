"""A matplotlib backend for tests (MPLBACKEND=module://roar_py_figure_backend): Agg's drawing with no
window, so pyplot.pause() does not redraw, and a blocking show() saves every open figure to
$ROAR_PY_FIGURE_DIR/figure_<n>.png."""
import os

from matplotlib import pyplot
from matplotlib.backend_bases import FigureManagerBase as FigureManager  # noqa: F401
from matplotlib.backends.backend_agg import FigureCanvasAgg


class FigureCanvas(FigureCanvasAgg):
    def draw_idle(self, *args, **kwargs):
        pass  # drawn once, when saved

    def start_event_loop(self, timeout=0):
        pass


def show(*args, block=None, **kwargs):
    if block is False:
        return  # pyplot.pause's show
    folder = os.environ.get("ROAR_PY_FIGURE_DIR", ".")
    for number in pyplot.get_fignums():
        pyplot.figure(number).savefig(os.path.join(folder, f"figure_{number}.png"))
