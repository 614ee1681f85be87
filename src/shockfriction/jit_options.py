"""numba compile options shared by the kernels.

``NO_REFCOUNT``: compile a kernel that allocates nothing without numba's reference counting (``_nrt=False``), so
that its array arguments and views cost no atomic increment/decrement per call (docs/theory/fused-cycle.md,
docs/theory/subgrid-layout.md section 6).  ``_nrt`` is a private numba option: a numba without it compiles the
same kernels with reference counting (same results, slower).

``VECTORIZE``: compile a kernel whose loop is to be vectorized (the serial force pass's block loop,
docs/theory/fused-cycle.md "SIMD force pass") with the loop vectorizer's width forced to ``SIMD_WIDTH`` while
that kernel compiles (LLVM's ``-force-vector-width``, reset to 0, the cost model's choice, after): the cost
model of AVX2 targets judges that loop not worth vectorizing, wrongly (measured).  Set through a compiler class
(numba's ``pipeline_class`` option); the vectorized loop computes each lane as the scalar loop (same results).
"""

import llvmlite.binding as llvm
from numba.core.compiler import Compiler
from numba.core.options import DefaultOptions

NO_REFCOUNT = {"_nrt": False} if hasattr(DefaultOptions, "_nrt") else {}

SIMD_WIDTH = 4  # float64 lanes: what LLVM itself picks on AVX-512 hosts (256-bit vectors)


class _VectorizingCompiler(Compiler):
    """numba's default compiler with the loop vectorizer's width forced to SIMD_WIDTH while it compiles."""

    def compile_extra(self, func):
        llvm.set_option("", f"-force-vector-width={SIMD_WIDTH}")
        try:
            return super().compile_extra(func)
        finally:
            llvm.set_option("", "-force-vector-width=0")


VECTORIZE = {"pipeline_class": _VectorizingCompiler}
