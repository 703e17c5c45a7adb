"""The decorators of the kernels.

Every kernel is compiled without Numba's reference counting (``_nrt=False``:
no allocation happens inside them) and releases the GIL.  Only the entry
kernels (:mod:`faultnet._kernels.events`, :mod:`faultnet._kernels.tree`) are
called from Python; the others are built without the Python and C wrappers
(``no_cpython_wrapper``), which saves compile time, and so can be called from
compiled code only (from Python they would crash).
"""

import numba as nb

__all__ = ["INNER", "entry", "inline_kernel", "kernel"]

#: options of the kernels called from compiled code only
INNER = {"nogil": True, "_nrt": False, "no_cpython_wrapper": True, "no_cfunc_wrapper": True}

#: a kernel called from other kernels
kernel = nb.njit(cache=True, **INNER)
#: a kernel inlined into its callers (Numba IR inlining, before typing)
inline_kernel = nb.njit(cache=True, inline="always", **INNER)
#: a kernel called from Python
entry = nb.njit(cache=True, nogil=True, _nrt=False)
