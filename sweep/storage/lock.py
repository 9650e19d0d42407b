"""One writer per output: the lock file of a parts directory."""

from __future__ import annotations

import datetime
import json
import os
import socket
from pathlib import Path

from sweep.errors import RunError
from sweep.storage.files import file_error

LOCK = "lock"


class Lock:
    """The lock file of a parts directory: one writer per output.

    Created with ``O_CREAT | O_EXCL`` (atomic on local file systems, NFSv3+ and Lustre),
    it records the holder's host, process id and start time.  A lock whose holder is a
    process of this host that no longer exists is stale and taken over; a lock held from
    another host is reported (it cannot be checked from here) and only ``break_lock``
    removes it.

    Parameters
    ----------
    parts : pathlib.Path
        The parts directory (it must exist).
    what : str
        What the holder does (``"run"``, ``"collect"``), recorded in the file.
    piece : (int, int), optional
        ``(I, N)``: the lock of piece I of N (``lock-piece-I-of-N``); pieces run side by
        side, and the whole-output lock excludes them all.
    """

    def __init__(self, parts: Path, what: str, piece: tuple[int, int] | None = None):
        name = LOCK if piece is None else f"{LOCK}-piece-{piece[0]}-of-{piece[1]}"
        self.path, self.what, self.piece, self.held = parts / name, what, piece, False

    def _conflicting(self) -> list[Path]:
        """Other locks that exclude this one: all others for the whole output, the
        whole-output lock for a piece."""
        if self.piece is None:
            return sorted(p for p in self.path.parent.glob(f"{LOCK}-piece-*") if p != self.path)
        whole = self.path.parent / LOCK
        return [whole] if whole.exists() else []

    def acquire(self, *, break_lock: bool = False) -> Lock:
        """Take the lock or raise :class:`RunError` naming its holder.

        The lock file is created first, then the conflicting locks are checked: of two
        processes starting at once at least one sees the other and backs off.
        """
        me = {"host": socket.gethostname(), "pid": os.getpid(), "what": self.what,
              "started": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds")}
        for _ in range(3):
            try:
                fd = os.open(self.path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
            except FileExistsError:
                Lock._check_free(self.path, break_lock)
                continue
            except OSError as exc:
                raise file_error(exc, "locking the parts directory") from None
            try:
                with os.fdopen(fd, "w") as f:
                    json.dump(me, f)
            except OSError as exc:
                self.path.unlink(missing_ok=True)
                raise file_error(exc, f"writing {self.path}") from None
            self.held = True
            try:
                for other in self._conflicting():
                    Lock._check_free(other, break_lock)
            except RunError:
                self.release()
                raise
            return self
        raise RunError(f"{self.path}: could not take the lock; try again")

    @staticmethod
    def _check_free(path: Path, break_lock: bool) -> None:
        """Remove the lock file ``path`` if it is stale or broken on request, else raise
        :class:`RunError` naming its holder."""
        holder = Lock.holder(path)
        if not path.exists():
            return
        if break_lock or Lock._stale(holder):
            # Rename, then delete: of two processes taking over one stale lock, only one
            # succeeds, and neither can delete a fresh lock the other just created.
            aside = path.with_name(f".{path.name}.stale-{os.getpid()}")
            try:
                path.rename(aside)
            except FileNotFoundError:
                return
            if Lock.holder(aside) != holder:  # replaced by a fresh lock in between: put it back
                aside.rename(path)
                raise RunError(f"{path}: taken by another process; try again")
            aside.unlink(missing_ok=True)
            return
        piece = f" ({path.name[len(LOCK) + 1:]})" if path.name != LOCK else ""
        raise RunError(
            f"{path.parent}/ is in use by a {holder.get('what', '?')}{piece} on host {holder.get('host', '?')}, "
            f"process {holder.get('pid', '?')}, since {holder.get('started', '?')}: wait for it to finish; if "
            "that process no longer exists (a job killed on another node), run again with --break-lock")

    @staticmethod
    def holder(path: Path) -> dict:
        """The contents of a lock file (empty when it cannot be read)."""
        try:
            return json.loads(path.read_text())
        except (OSError, ValueError):
            return {}

    @staticmethod
    def _stale(holder: dict) -> bool:
        # Only a process of this host can be checked; an unreadable lock is left alone.
        if holder.get("host") != socket.gethostname() or not isinstance(holder.get("pid"), int):
            return False
        try:
            os.kill(holder["pid"], 0)
        except ProcessLookupError:
            return True
        except PermissionError:
            return False
        return False

    def release(self) -> None:
        """Remove the lock file if this object holds it."""
        if self.held:
            self.path.unlink(missing_ok=True)
            self.held = False

    def __enter__(self) -> Lock:
        return self.acquire()

    def __exit__(self, *exc) -> None:
        self.release()
