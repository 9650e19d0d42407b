"""Errors of a run that are not about the job file's contents (those are ``JobError``)."""

from __future__ import annotations


class RunError(RuntimeError):
    """A run cannot start or did not finish: refused resume, failed task, missing files.

    Parameters
    ----------
    message : str
        One clear line for the user.
    details : str
        Optional longer text shown before it (tracebacks of the failing tasks).
    """

    def __init__(self, message: str, details: str = ""):
        super().__init__(message)
        self.message, self.details = message, details
