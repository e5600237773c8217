"""Transcendental functions whose bits do not depend on numpy's SIMD dispatch.

numpy evaluates ``sin``, ``cos``, ``tan``, ``arctan``, ``arctan2`` and ``arccos`` of
float64 arrays with vectorised kernels chosen at run time from the CPU's features: on
a CPU with AVX-512 they are numpy's own SIMD code, elsewhere the C library's. The two
differ in the last bit for some inputs. In a search (CMA-ES ranks its samples by
fitness) one such bit can reorder two nearly equal samples and send a run elsewhere,
so the same task gave another arm on another machine (issue 27).

The functions here apply Python's :mod:`math` (the C library's ``libm``, one element
at a time) to every element: the same bits whether or not numpy's SIMD kernels are
enabled (``NPY_DISABLE_CPU_FEATURES``). Their cost is about 60 ns an element: use
them where a result feeds a search, not on large meshes. Angles are radians.
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

import math
from collections.abc import Callable

import numpy as np

__all__ = ["arccos", "arctan", "arctan2", "canonical_eigh", "cos", "sin", "tan"]


def _unary(
    f: Callable[[float], float], name: str | None = None
) -> Callable[[np.ndarray], np.ndarray]:
    """``f`` of every element; ``name``: the ``math`` function it is (default ``f``'s name)."""

    def apply(x) -> np.ndarray:
        a = np.asarray(x, dtype=float)
        out = np.fromiter(map(f, a.ravel().tolist()), dtype=float, count=a.size)
        return out.reshape(a.shape)

    apply.__name__ = f.__name__
    apply.__doc__ = f"``math.{name or f.__name__}`` of every element (radians), as a float64 array."
    return apply


def _acos(v: float) -> float:
    # numpy's arccos gives NaN outside [-1, 1] where math.acos raises
    return math.acos(v) if -1.0 <= v <= 1.0 else math.nan


sin = _unary(math.sin)
cos = _unary(math.cos)
tan = _unary(math.tan)
arctan = _unary(math.atan)
arccos = _unary(_acos, "acos")  # math.acos, NaN outside [-1, 1]
arccos.__name__ = "arccos"


def arctan2(y, x) -> np.ndarray:
    """``math.atan2(y, x)`` of every pair of broadcast elements, radians."""
    a, b = np.broadcast_arrays(np.asarray(y, dtype=float), np.asarray(x, dtype=float))
    vals = map(math.atan2, a.ravel().tolist(), b.ravel().tolist())
    return np.fromiter(vals, dtype=float, count=a.size).reshape(a.shape)


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
