"""One thread per rank: importing this module sets the thread counts of numba and BLAS.

It must be imported before numpy or numba (``sweep.cli`` imports it first).  Values the
user has already set are kept, so a task that wants threads can ask for them.
"""

import os

for _name in ("NUMBA_NUM_THREADS", "OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_name, "1")
