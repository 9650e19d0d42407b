"""Tasks counted by status, with the commonest reasons of those not ok."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from sweep.analyses.base import STATUS_FAILED, STATUS_MEANINGS, STATUS_NOT_CONVERGED, STATUS_OK, STATUS_SKIPPED

#: ``status`` of a task whose chunk has not been computed (a partial collect).
STATUS_MISSING = -1
#: CF ``flag_values`` and ``flag_meanings`` of the published ``status`` variable.
STATUS_FLAG_VALUES = np.array([STATUS_MISSING, 0, 1, 2, 3], dtype=np.int8)
STATUS_FLAG_MEANINGS = "missing " + STATUS_MEANINGS


def summarize(counts: Mapping[int, int], reasons: Mapping[tuple[int, str], int], top: int = 3) -> str:
    """Counts per status with the commonest reasons of the tasks that are not ok."""
    out = []
    for code, name in ((STATUS_OK, "ok"), (STATUS_NOT_CONVERGED, "not converged"), (STATUS_FAILED, "failed")):
        n = counts.get(code, 0)
        why = sorted(((c, m) for (s, m), c in reasons.items() if s == code and m), key=lambda x: (-x[0], x[1]))
        detail = "; ".join(f"{c}: {m}" for c, m in why[:top])
        more = "" if len(why) <= top else f"; {len(why) - top} other reason(s)"
        out.append(f"{n} {name}" + (f" ({detail}{more})" if detail else ""))
    if counts.get(STATUS_SKIPPED, 0):
        out.append(f"{counts[STATUS_SKIPPED]} outside the cases")
    return ", ".join(out)
