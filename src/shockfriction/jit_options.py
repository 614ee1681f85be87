"""numba compile options shared by the kernels.

``NO_REFCOUNT``: compile a kernel that allocates nothing without numba's reference counting (``_nrt=False``), so
that its array arguments and views cost no atomic increment/decrement per call (docs/theory/fused-cycle.md,
docs/theory/subgrid-layout.md section 6).  ``_nrt`` is a private numba option: a numba without it compiles the
same kernels with reference counting (same results, slower).
"""

from numba.core.options import DefaultOptions

NO_REFCOUNT = {"_nrt": False} if hasattr(DefaultOptions, "_nrt") else {}
