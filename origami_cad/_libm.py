"""Transcendental functions whose bits do not depend on numpy's SIMD dispatch.

numpy evaluates ``sin``, ``cos``, ``tan``, ``arctan``, ``arctan2`` and ``arccos`` of
float64 arrays with vectorised kernels chosen at run time from the CPU's features: on
a CPU with AVX-512 they are numpy's own SIMD code, elsewhere the C library's. The two
differ in the last bit for some inputs. In a search (CMA-ES ranks its samples by
fitness) one such bit can reorder two nearly equal samples and send a run elsewhere,
so the same task gave another arm on another machine.

The functions here call the C library's scalar functions (``libm``, the same
Python's :mod:`math` calls) on every element, from a compiled loop: the same bits
whether or not numpy's SIMD kernels are enabled (``NPY_DISABLE_CPU_FEATURES``), and
the same bits as :mod:`math`. The loops are compiled without fast-math and without a
vector math library: where numba would vectorise them with Intel's SVML (numba's
``USING_SVML``), they fall back to :mod:`math` one element at a time (about 60 ns an
element instead of about 10). Angles are radians.
:func:`canonical_eigh` is the eigen-decomposition both CMA-ES searches (the arm's and the
route planner's) use, so it sits here, below both.

>>> import numpy as np
>>> x = np.linspace(-3.0, 3.0, 7)
>>> bool(np.allclose(sin(x), np.sin(x), rtol=0, atol=1e-15))
True
>>> arctan2(np.array([1.0, -1.0]), 1.0).tolist() == [math.atan2(1, 1), math.atan2(-1, 1)]
True
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable

import numpy as np

__all__ = ["arccos", "arctan", "arctan2", "canonical_eigh", "cos", "sin", "tan"]


def _python_unary(f: Callable[[float], float]) -> Callable[[np.ndarray, np.ndarray], None]:
    def loop(a: np.ndarray, out: np.ndarray) -> None:
        out[:] = np.fromiter(map(f, a.tolist()), dtype=float, count=a.size)

    return loop


def _python_binary(f: Callable[[float, float], float]):
    def loop(a: np.ndarray, b: np.ndarray, out: np.ndarray) -> None:
        out[:] = np.fromiter(map(f, a.tolist(), b.tolist()), dtype=float, count=a.size)

    return loop


def _acos(v: float) -> float:
    # numpy's arccos gives NaN outside [-1, 1] where math.acos raises
    return math.acos(v) if -1.0 <= v <= 1.0 else math.nan


@functools.cache
def _loops() -> dict[str, Callable]:
    """The element loops by name: compiled (numba, libm's scalar calls), else :mod:`math`."""
    import numba

    python = {
        "sin": _python_unary(math.sin),
        "cos": _python_unary(math.cos),
        "tan": _python_unary(math.tan),
        "atan": _python_unary(math.atan),
        "acos": _python_unary(_acos),
        "atan2": _python_binary(math.atan2),
    }
    if numba.config.USING_SVML or numba.config.DISABLE_JIT:
        return python
    jit = numba.njit(cache=True, fastmath=False, nogil=True)

    @jit
    def sin_loop(a, out):  # pragma: no cover - compiled
        for i in range(a.size):
            out[i] = math.sin(a[i])

    @jit
    def cos_loop(a, out):  # pragma: no cover - compiled
        for i in range(a.size):
            out[i] = math.cos(a[i])

    @jit
    def tan_loop(a, out):  # pragma: no cover - compiled
        for i in range(a.size):
            out[i] = math.tan(a[i])

    @jit
    def atan_loop(a, out):  # pragma: no cover - compiled
        for i in range(a.size):
            out[i] = math.atan(a[i])

    @jit
    def acos_loop(a, out):  # pragma: no cover - compiled
        for i in range(a.size):
            v = a[i]
            out[i] = math.acos(v) if -1.0 <= v <= 1.0 else math.nan

    @jit
    def atan2_loop(a, b, out):  # pragma: no cover - compiled
        for i in range(a.size):
            out[i] = math.atan2(a[i], b[i])

    return {
        "sin": sin_loop,
        "cos": cos_loop,
        "tan": tan_loop,
        "atan": atan_loop,
        "acos": acos_loop,
        "atan2": atan2_loop,
    }


def _contiguous(x) -> np.ndarray:
    """``x`` as a C-contiguous float64 array of its own shape (0-d stays 0-d)."""
    a = np.asarray(x, dtype=float)
    return a if a.flags.c_contiguous else a.copy()


def _unary(loop: str, name: str) -> Callable[[np.ndarray], np.ndarray]:
    """libm's ``loop`` function of every element (:mod:`math`'s ``name``)."""

    def apply(x) -> np.ndarray:
        a = _contiguous(x)
        out = np.empty(a.shape)
        _loops()[loop](a.reshape(-1), out.reshape(-1))
        return out

    apply.__name__ = name
    apply.__doc__ = f"``math.{loop}`` of every element (radians), as a float64 array."
    return apply


sin = _unary("sin", "sin")
cos = _unary("cos", "cos")
tan = _unary("tan", "tan")
arctan = _unary("atan", "arctan")
arccos = _unary("acos", "arccos")  # NaN outside [-1, 1], as numpy's
arccos.__doc__ = "``math.acos`` of every element (radians), NaN outside [-1, 1]."


def arctan2(y, x) -> np.ndarray:
    """``math.atan2(y, x)`` of every pair of broadcast elements, radians."""
    a, b = np.broadcast_arrays(np.asarray(y, dtype=float), np.asarray(x, dtype=float))
    a, b = _contiguous(a), _contiguous(b)
    out = np.empty(a.shape)
    _loops()["atan2"](a.reshape(-1), b.reshape(-1), out.reshape(-1))
    return out


def canonical_eigh(C: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``numpy.linalg.eigh`` with each eigenvector's sign fixed: its largest entry positive.

    An eigenvector's sign is arbitrary, and LAPACK may return either for two matrices
    that differ in their last bits (as CMA-ES's covariance does from one CPU's numpy
    kernels to another's); CMA-ES then samples other points from the same random
    numbers and the run goes elsewhere. Fixed signs make the samples depend on the
    matrix, not on those bits.
    """
    d, b = np.linalg.eigh(C)
    rows = np.argmax(np.abs(b), axis=0)
    return d, b * np.where(b[rows, np.arange(b.shape[1])] < 0, -1.0, 1.0)
