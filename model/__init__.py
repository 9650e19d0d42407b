"""Physics and numerics of the pre-stretched hyperelastic annular membrane.

Pure numpy/scipy/numba: no MPI, no xarray, no files other than numba's cache.

numba's on-disk cache checks only the source file of each compiled function, not the
files of the functions it calls, so an edit of ``rom.py`` could leave a stale kernel of
``integrate.py`` in use.  Unless ``NUMBA_CACHE_DIR`` is set, the cache therefore lives in
a directory named after a hash of this package's sources: any change of any module gives
a fresh cache.
"""

import hashlib
import os
import sys
from pathlib import Path


def _cache_dir() -> str:
    sources = sorted(Path(__file__).parent.rglob("*.py"))  # subpackages (model/full) included
    digest = hashlib.sha256(b"".join(p.read_bytes() for p in sources)).hexdigest()[:16]
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(base, "membrane-sweep", f"numba-{digest}")


os.environ.setdefault("NUMBA_CACHE_DIR", _cache_dir())
if "numba" in sys.modules:  # imported before this package: its configuration is read already
    sys.modules["numba"].config.CACHE_DIR = os.environ["NUMBA_CACHE_DIR"]
