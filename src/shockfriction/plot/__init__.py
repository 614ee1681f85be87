"""Matplotlib figures written to files, never windows.

Figures are :class:`matplotlib.figure.Figure` objects drawn by the Agg canvas: the
package never calls ``matplotlib.use`` nor touches pyplot's state, so importing or
running it leaves a user's backend (notebook, GUI) as it was.
"""

from __future__ import annotations


def subplots(nrows: int = 1, ncols: int = 1, *, figsize=None, constrained_layout: bool = False, **kwargs):
    """``(fig, axes)`` as :func:`matplotlib.pyplot.subplots`, on an Agg canvas outside pyplot."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize, layout="constrained" if constrained_layout else None)
    FigureCanvasAgg(fig)
    return fig, fig.subplots(nrows, ncols, **kwargs)
