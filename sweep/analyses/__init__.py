"""Registry of analyses: ``[job] analysis = name`` -> an :class:`~sweep.analyses.base.Analysis`.

Entries are ``"module:attribute"`` strings resolved lazily with :mod:`importlib`, so that
importing the command line does not import (and compile the numba kernels of) every
analysis.

Tests and benchmarks add analyses of their own through the environment variable
``SWEEP_EXTRA_ANALYSES``: comma-separated ``name=module:attribute`` items, for example
``SWEEP_EXTRA_ANALYSES="fake=fake_analysis:FAKE"`` with the module on ``PYTHONPATH``.
"""

from __future__ import annotations

import importlib
import os

from sweep.analyses.base import Analysis, JobError

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


def _extra_entries() -> dict[str, str]:
    entries = {}
    for item in filter(None, (s.strip() for s in os.environ.get(EXTRA_ENV, "").split(","))):
        name, sep, target = item.partition("=")
        if not sep or ":" not in target:
            raise JobError(EXTRA_ENV, item, "comma-separated name=module:attribute items")
        entries[name.strip()] = target.strip()
    return entries


def registry() -> dict[str, str]:
    """The analyses available in this installation.

    Returns
    -------
    dict of str to str
        ``name -> "module:attribute"``: the built-in analyses, then the entries of
        ``SWEEP_EXTRA_ANALYSES``.
    """
    return {**BUILTIN, **_extra_entries()}


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
    entries = registry()
    if name not in entries:
        raise JobError("job.analysis", name, "one of the available analyses: "
                       + (", ".join(repr(n) for n in entries) or "none is installed"))
    module_name, _, attribute = entries[name].partition(":")
    analysis = getattr(importlib.import_module(module_name), attribute)
    if not isinstance(analysis, Analysis):
        raise TypeError(f"{entries[name]} is a {type(analysis).__name__}, not an Analysis")
    if hasattr(analysis, "warmup"):  # the protocol before warmups: it would be ignored
        raise TypeError(f"{entries[name]} defines warmup(options); the runner calls warmups(options), a list "
                        "of calls (sweep/analyses/base.py)")
    return analysis
