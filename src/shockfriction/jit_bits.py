"""Bit casts between float64 and 64-bit integers for numba kernels (LLVM ``bitcast``: free, and
vectorisable, unlike a libm call or a view of an array).

* :func:`f64_from_bits`: the float64 whose bit pattern is the 64-bit integer ``bits``.
* :func:`f64_bits`: the bit pattern of a float64 as uint64.  For x >= 0 (and not NaN) the order
  of the patterns is the order of the values, so that a min reduction over non-negative floats can
  run in unsigned integers (which LLVM vectorises; an fp min reduction it does not, without
  fast-math); NaN and negative values map above +inf.
"""

from llvmlite import ir
from numba import types
from numba.extending import intrinsic


@intrinsic
def f64_from_bits(typingctx, bits):
    """The float64 whose bit pattern is ``bits`` (int64 or uint64)."""
    if not (isinstance(bits, types.Integer) and bits.bitwidth == 64):
        return None
    sig = types.float64(bits)

    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.DoubleType())

    return sig, codegen


@intrinsic
def f64_bits(typingctx, x):
    """The bit pattern of the float64 ``x``, as uint64."""
    if x != types.float64:
        return None
    sig = types.uint64(types.float64)

    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.IntType(64))

    return sig, codegen
