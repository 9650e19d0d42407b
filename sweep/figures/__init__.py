"""Every figure of ``python -m sweep figures``: one module per analysis (Figs. 2-19).

Each module's ``<analysis>_figures(ds, outdir)`` takes the published Dataset and an output
directory and returns the list of paths it wrote; :func:`drawer` finds it by the
analysis' name, and an analysis registered through ``SWEEP_EXTRA_ANALYSES`` adds its own
with :func:`register`.  :func:`draw` is the entry point (the command line's and a script's): it
applies the house style and the chosen format, resolution and style file inside a
``matplotlib.rc_context``, so the caller's ``rcParams`` and backend are left as they
were.  matplotlib is imported lazily.  Grid values are labelled with the symbols of
:data:`sweep.figures.panels.SYMBOLS`.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from sweep.figures.output import COLLECTOR, OUTPUT

#: The house style, applied by :func:`draw` (a style file given to it comes on top).
HOUSE_STYLE = {"figure.dpi": 120, "axes.grid": True, "grid.alpha": 0.3, "font.size": 10,
               "legend.fontsize": 8, "savefig.bbox": "tight"}
#: Output formats of :func:`draw`.
FORMATS = ("png", "pdf", "svg")
#: Figure functions of extra analyses, by analysis name (:func:`register`).
_REGISTERED: dict[str, Callable] = {}


def register(analysis: str, drawer: Callable) -> None:
    """Draw the results of the analysis named ``analysis`` with ``drawer(ds, outdir)``
    (returning the paths written), e.g. from the module of an extra analysis."""
    _REGISTERED[analysis] = drawer


def drawer(analysis: str) -> Callable | None:
    """The figure function of the analysis named ``analysis`` (its module's, or the one
    given to :func:`register`), or None if it has none."""
    from sweep.figures import backbone, basins, continuation, linear, response, static

    built_in = {"static": static.static_figures, "linear": linear.linear_figures,
                "backbone": backbone.backbone_figures, "continuation": continuation.continuation_figures,
                "response": response.response_figures, "basins": basins.basins_figures}
    return _REGISTERED.get(analysis, built_in.get(analysis))


def comparer(analysis: str) -> Callable | None:
    """The function that draws several results of the analysis named ``analysis`` together
    (``comparer(name)(datasets, outdir)``), or None: the backbones (Fig. 10 across models) and
    the forced branches (ROM against the full model)."""
    from sweep.figures import backbone, continuation

    return {"backbone": backbone.backbone_comparison,
            "continuation": continuation.continuation_comparison}.get(analysis)


def draw_comparison(analysis, datasets, outdir, *, fmt: str = "png", dpi: float | None = None,
                    style=None) -> list[Path]:
    """The figures comparing several results of ``analysis`` (:func:`comparer`), written to
    ``outdir`` with the options of :func:`draw`; none when the analysis has no comparison."""
    function = comparer(analysis.name)
    if function is None:
        return []
    return _written(lambda where: function(list(datasets), where), outdir, fmt, dpi, style)


def draw(analysis, ds, outdir, *, fmt: str = "png", dpi: float | None = None, style=None) -> list[Path]:
    """The standard figures of a result, written to ``outdir``.

    Parameters
    ----------
    analysis : sweep.analyses.base.Analysis
        The analysis that wrote ``ds`` (``sweep.analyses.get(ds.attrs["analysis"])``).
    ds : xarray.Dataset
        The result.
    outdir : path
        Output directory (created).
    fmt : {"png", "pdf", "svg"}
        File format (PDF and SVG are vector; the basins images are embedded rasters).
    dpi : float, optional
        Resolution of raster output (default 120, basins 150).
    style : str or path, optional
        A matplotlib style (name or ``.mplstyle`` file) applied on top of the house style.

    Returns
    -------
    list of pathlib.Path
    """
    return _written(lambda where: _figures(analysis, ds, where), outdir, fmt, dpi, style)


def _written(drawing, outdir, fmt: str, dpi: float | None, style) -> list[Path]:
    """``drawing(outdir)`` under the house style (and ``style``) with the files written in
    ``fmt`` at ``dpi`` into ``outdir`` (created); the caller's ``rcParams`` are left alone."""
    import matplotlib.pyplot as plt

    if fmt not in FORMATS:
        raise ValueError(f"fmt = {fmt!r} is invalid: must be one of {', '.join(FORMATS)}")
    Path(outdir).mkdir(parents=True, exist_ok=True)
    token = OUTPUT.set((fmt, dpi))
    try:
        with plt.rc_context(HOUSE_STYLE):
            if style is not None:
                plt.style.use(style)
            return drawing(Path(outdir))
    finally:
        OUTPUT.reset(token)


def make(analysis, ds, style=None) -> dict:
    """The standard figures of a result as matplotlib ``Figure`` objects, nothing written.

    Parameters
    ----------
    analysis : sweep.analyses.base.Analysis
        The analysis that wrote ``ds``.
    ds : xarray.Dataset
        The result.
    style : str or path, optional
        A matplotlib style on top of the house style (applied while drawing).

    Returns
    -------
    dict of str to matplotlib.figure.Figure
        By file stem (``"bifurcation_P0"``, ``"backbone"``, ...; ``"modes_1_0-2_0/backbone"``
        for a result over mode sets), for the caller to adjust,
        show or save; the caller's ``rcParams`` and backend are left alone.
    """
    import matplotlib.pyplot as plt

    figures: dict = {}
    token = COLLECTOR.set(figures)
    try:
        with plt.rc_context(HOUSE_STYLE):
            if style is not None:
                plt.style.use(style)
            _figures(analysis, ds, Path("."))
    finally:
        COLLECTOR.reset(token)
    return figures


def _figures(analysis, ds, outdir: Path) -> list:
    """Draw ``ds`` with the figure function of ``analysis``; a result over mode sets is drawn
    set by set (:func:`sweep.figures.mode_sets.per_set_figures`)."""
    function = drawer(analysis.name)
    if function is None:
        return []
    if "mode_set" in ds.dims:
        from sweep.figures.mode_sets import per_set_figures

        return per_set_figures(function, ds, outdir, analysis.name)
    return function(ds, outdir)
