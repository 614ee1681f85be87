"""LLVM instructions that numba does not offer, for the kernels: bit casts between float64 and 64-bit integers
(LLVM ``bitcast``: free, and vectorisable, unlike a libm call or a view of an array), and an atomic counter.

* :func:`f64_from_bits`: the float64 whose bit pattern is the 64-bit integer ``bits``.
* :func:`f64_bits`: the bit pattern of a float64 as uint64.  For x >= 0 (and not NaN) the order
  of the patterns is the order of the values, so that a min reduction over non-negative floats can
  run in unsigned integers (which LLVM vectorises; an fp min reduction it does not, without
  fast-math); NaN and negative values map above +inf.
* :func:`fetch_add`: add 1 to an int64 array element atomically and return its value before: the work queue of
  the parallel loops that hand their items out one at a time (numba's ``prange`` gives each thread a fixed
  contiguous share of the iterations, whatever ``parallel_chunksize`` says, on its OpenMP and workqueue layers;
  docs/theory/threads.md, "A work queue for the partitions").
"""

from llvmlite import ir
from numba import types
from numba.core import cgutils
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


@intrinsic
def fetch_add(typingctx, counter, index):
    """``counter[index] += 1`` as one atomic instruction (LLVM ``atomicrmw add``, monotonic order); returns the
    value before.  Threads that take items by it each get a different one: item k goes to the k-th call, whichever
    thread makes it.  ``counter``: a C-contiguous int64 array."""
    if not (isinstance(counter, types.Array) and counter.dtype == types.int64 and counter.layout == "C"
            and isinstance(index, types.Integer)):
        return None
    sig = types.int64(counter, index)

    def codegen(context, builder, signature, args):
        arrty = signature.args[0]
        ary = context.make_array(arrty)(context, builder, args[0])
        ptr = cgutils.get_item_pointer(context, builder, arrty, ary, [args[1]], wraparound=False)
        return builder.atomic_rmw("add", ptr, ir.Constant(ir.IntType(64), 1), "monotonic")

    return sig, codegen
