"""Lazy registries of named plug-ins: ``name -> "module:attribute"``.

The analyses (``[job] analysis``, :mod:`sweep.analyses`) and the models (``[model] kind``,
:mod:`sweep.models`) are registered by name.  Entries are resolved with :mod:`importlib`
on first use, so that importing the command line imports (and compiles the numba kernels
of) no plug-in; tests, benchmarks and users add entries of their own through an
environment variable of comma-separated ``name=module:attribute`` items, with the module
on ``PYTHONPATH`` (it is read in every MPI rank).
"""

from __future__ import annotations

import importlib
import os
from collections.abc import Mapping

from sweep.job_errors import JobError


class Registry:
    """Named plug-ins of one kind.

    Parameters
    ----------
    what : str
        What the entries are, for messages (``"analyses"``, ``"models"``).
    key : str
        The job-file key that names an entry (``"job.analysis"``, ``"model.kind"``).
    builtin : Mapping of str to str
        ``name -> "module:attribute"`` of the built-in entries.
    env : str
        The environment variable with extra ``name=module:attribute`` entries.
    """

    def __init__(self, what: str, key: str, builtin: Mapping[str, str], env: str):
        self.what, self.key, self.builtin, self.env = what, key, dict(builtin), env

    def _extra(self) -> dict[str, str]:
        entries = {}
        for item in filter(None, (s.strip() for s in os.environ.get(self.env, "").split(","))):
            name, sep, target = item.partition("=")
            if not sep or ":" not in target:
                raise JobError(self.env, item, "comma-separated name=module:attribute items")
            entries[name.strip()] = target.strip()
        return entries

    def entries(self) -> dict[str, str]:
        """``name -> "module:attribute"``: the built-in entries, then those of the
        environment variable."""
        return {**self.builtin, **self._extra()}

    def load(self, name: str):
        """Import and return the entry registered as ``name``.

        Raises
        ------
        JobError
            If no entry of that name is available (the message lists those that are).
        """
        entries = self.entries()
        if name not in entries:
            raise JobError(self.key, name, f"one of the available {self.what}: "
                           + (", ".join(repr(n) for n in entries) or "none is installed"))
        module_name, _, attribute = entries[name].partition(":")
        return getattr(importlib.import_module(module_name), attribute)
