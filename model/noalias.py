"""A numba compiler pipeline for kernels whose array arguments never overlap in memory.

LLVM vectorises a loop only if it can prove that the loop's stores do not change what it
loads.  For a table lookup (a gather: ``coef[idx[b]]``) it cannot compute the addresses
read, so without further information every loop that stores and gathers stays scalar.
:class:`NoAliasCompiler` marks every pointer argument of the compiled function
``noalias`` (numba's ``noalias`` flag, which ``njit`` does not expose as an option), so the
lock-step kernels of :mod:`model.integrate` vectorise across trajectories with hardware
gathers.

Contract of a kernel compiled with it: **no two array arguments may share memory** (not
two views of one array, not an array and a slice of it).  Breaking it is undefined
behaviour, not an error.  Arrays allocated inside the kernel are not concerned.
"""

from __future__ import annotations

from numba.core.compiler import Compiler


class NoAliasCompiler(Compiler):
    """numba pipeline (``njit(pipeline_class=NoAliasCompiler)``) that compiles with the
    ``noalias`` flag: pointer arguments are declared non-overlapping."""

    def __init__(self, typingctx, targetctx, library, args, return_type, flags, locals):
        flags.noalias = True
        super().__init__(typingctx, targetctx, library, args, return_type, flags, locals)
