"""Errors of job files: one line naming the dotted key, the value and what is allowed.

A leaf module (no import of the package's others), so that every layer that validates a
part of a job file (the job file itself, the analyses' options, the models' ``[model]``
tables, the registries) raises the same errors.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any


class _Missing:
    """Type of :data:`MISSING`."""

    def __repr__(self) -> str:
        return "<missing>"


#: The ``value`` of a :class:`JobError` for a required key that is absent, so the message
#: reads ``job.name = <missing> is invalid: ...``.
MISSING = _Missing()


class JobError(ValueError):
    """A job file is invalid.  The message names the key, the value and what is allowed."""

    def __init__(self, key: str, value: Any, allowed: str):
        self.key, self.value, self.allowed = key, value, allowed
        super().__init__(f"{key} = {value!r} is invalid: {allowed}")


class JobErrors(JobError):
    """Several problems of one job file, all reported at once (one line each)."""

    def __init__(self, errors: list[JobError]):
        self.errors = errors
        first = errors[0]
        ValueError.__init__(self, "\n".join(str(e) for e in errors))
        self.key, self.value, self.allowed = first.key, first.value, first.allowed


def check_keys(table: Mapping[str, Any], section: str, allowed) -> None:
    """Reject the first key of ``table`` that is not in ``allowed`` (a :class:`JobError`).

    ``section`` is the dotted name of the table (``"job"``, ``"grid.delta"``,
    ``"continuation"``); the message lists the allowed keys in the order given.
    """
    for key, value in table.items():
        if key not in allowed:
            raise JobError(f"{section}.{key}", value,
                           f"unknown key; the keys of [{section}] are " + ", ".join(allowed))
