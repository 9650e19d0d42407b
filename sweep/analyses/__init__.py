"""Registry of analyses: ``[job] analysis = name`` -> an :class:`~sweep.analyses.base.Analysis`.

Entries are ``"module:attribute"`` strings resolved lazily with :mod:`importlib`, so that
importing the command line does not import (and compile the numba kernels of) every
analysis.

Tests and benchmarks add analyses of their own through the environment variable
``SWEEP_EXTRA_ANALYSES``: comma-separated ``name=module:attribute`` items, for example
``SWEEP_EXTRA_ANALYSES="fake=fake_analysis:FAKE"`` with the module on ``PYTHONPATH``.
"""

from __future__ import annotations

from sweep.analyses.base import Analysis
from sweep.registry import Registry

#: Environment variable with extra ``name=module:attribute`` entries (tests, benchmarks).
EXTRA_ENV = "SWEEP_EXTRA_ANALYSES"

BUILTIN = {
    "static": "sweep.analyses.static:STATIC",
    "linear": "sweep.analyses.linear:LINEAR",
    "backbone": "sweep.analyses.backbone:BACKBONE",
    "response": "sweep.analyses.response:RESPONSE",
    "continuation": "sweep.analyses.continuation:CONTINUATION",
    "basins": "sweep.analyses.basins:BASINS",
}


_REGISTRY = Registry("analyses", "job.analysis", BUILTIN, EXTRA_ENV)


def registry() -> dict[str, str]:
    """The analyses available in this installation.

    Returns
    -------
    dict of str to str
        ``name -> "module:attribute"``: the built-in analyses, then the entries of
        ``SWEEP_EXTRA_ANALYSES``.
    """
    return _REGISTRY.entries()


def get(name: str) -> Analysis:
    """Import and return the analysis registered as ``name``.

    Parameters
    ----------
    name : str
        The ``[job] analysis`` value.

    Returns
    -------
    Analysis
        The analysis instance.

    Raises
    ------
    JobError
        If no analysis of that name is available (the message lists those that are).
    """
    analysis = _REGISTRY.load(name)
    entry = registry()[name]
    if not isinstance(analysis, Analysis):
        raise TypeError(f"{entry} is a {type(analysis).__name__}, not an Analysis")
    if hasattr(analysis, "warmup"):  # the protocol before warmups: it would be ignored
        raise TypeError(f"{entry} defines warmup(options); the runner calls warmups(options), a list "
                        "of calls (sweep/analyses/base.py)")
    return analysis
