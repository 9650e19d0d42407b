"""Where a figure goes: written in the format of :func:`sweep.figures.draw`, or handed
back by :func:`sweep.figures.make`; matplotlib imported lazily."""

from __future__ import annotations

import contextvars
from pathlib import Path

#: ``(format, dpi)`` of the figures being written, set by :func:`sweep.figures.draw`.
OUTPUT = contextvars.ContextVar("figure_output", default=("png", None))
#: The dict collecting the figures under :func:`sweep.figures.make` (None: write them).
COLLECTOR = contextvars.ContextVar("figure_collector", default=None)


def pyplot():
    """``matplotlib.pyplot`` (its backend and ``rcParams`` untouched)."""
    import matplotlib.pyplot as plt

    return plt


def save_figure(fig, outdir, name, dpi: float | None = None) -> Path:
    """Save ``fig`` as ``outdir/name`` in the format of :func:`sweep.figures.draw` (the suffix
    of ``name`` is replaced), close it, return the path.  ``dpi`` is this figure's default
    resolution.  Under :func:`sweep.figures.make` the figure is handed back instead (nothing
    is written)."""
    import matplotlib.pyplot as plt

    collected = COLLECTOR.get()
    if collected is not None:
        key = Path(name).stem if Path(outdir) == Path(".") else f"{Path(outdir).as_posix()}/{Path(name).stem}"
        collected[key] = fig
        return Path(name)
    fmt, chosen = OUTPUT.get()
    path = (Path(outdir) / name).with_suffix("." + fmt)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, format=fmt, **({"dpi": chosen or dpi} if chosen or dpi else {}))
    plt.close(fig)
    return path
