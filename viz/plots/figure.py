"""One matplotlib Figure factory for every plot module (no pyplot, no global registry)."""

from __future__ import annotations

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure


def new_figure(width_in: float, height_in: float) -> Figure:
    """A matplotlib Figure [inches] on an Agg canvas, without pyplot."""
    fig = Figure(figsize=(width_in, height_in))
    FigureCanvasAgg(fig)
    return fig
