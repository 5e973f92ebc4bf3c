"""Argument checks and conversions shared by the integrators (private).

Arguments are checked once, at the public boundary: ValueError (or the
:class:`~lighting._validate.ArgumentTypeError` TypeError for text, complex or
objects) naming the parameter, the value and what is allowed; sample counts
are estimated against the memory budget (:func:`lighting._budget.check_budget`)
before anything is allocated.  All integration runs in float64; results are
returned in the working dtype of the array inputs (float32 in, float32 out) by :func:`_out`.
"""

from __future__ import annotations

import numpy as np

from .._budget import check_budget
from .._text import plural
from .._validate import check_count
from ..sampling.base import BYTES_PER_SAMPLE
from ..sampling.brdf import _check_brdf  # noqa: F401  (_check_brdf: the one "is it a BRDF" check)

_NODE_BUDGET = 1 << 18  # directions evaluated per vectorized batch (bounds memory)


def _samples(value, minimum=1, method=None, brdf=None, points=1) -> int:
    """``samples``: an integer >= ``minimum`` whose largest batch fits the memory budget."""
    n = check_count("samples", value, minimum)
    parts = 1 if brdf is None else len(brdf.parts)
    # One batch holds max(n, _NODE_BUDGET) directions; mixtures draw a candidate per part.
    peak = max(n, min(_NODE_BUDGET, n * max(int(points), 1))) * BYTES_PER_SAMPLE * (1 + parts)
    check_budget("samples", peak, what=f"{n} directions per point, {plural(parts, 'part')}")
    return n


def _default_replicates(samples: int) -> int:
    return int(np.clip(samples // 64, 2, 16))


def _replicates(replicates, samples):
    """``replicates`` of the stratified method: given in ``[2, samples]``, or ``clip(samples // 64, 2, 16)``."""
    if replicates is None:
        return _default_replicates(samples)
    return check_count("replicates", replicates, 2, max(2, samples))


def _out(x, dt):
    """A float64 result in the caller's dtype ``dt``: NaN as 0, saturated at the dtype's largest value."""
    big = float(np.finfo(dt).max)
    return np.clip(np.nan_to_num(np.asarray(x, dtype=np.float64), nan=0.0), -big, big).astype(dt)


def _unit_rows(d: np.ndarray, fallback):
    """Unit vectors along float64 vectors ``d`` ``(..., 3)``, ``fallback`` for zero vectors; and their lengths.

    Each vector is first scaled by its largest component, so the lengths of huge finite vectors do not
    overflow.  Returns ``(unit, length)``, ``length`` ``(..., 1)`` that of the scaled vector (0 for a zero
    vector).
    """
    d = d / np.maximum(np.max(np.abs(d), axis=-1, keepdims=True), np.finfo(np.float64).tiny)
    length = np.sqrt(np.sum(d * d, axis=-1, keepdims=True))
    d = np.where(length > 0, d / np.where(length > 0, length, 1.0), fallback)  # length in [1, √3] or replaced by 1
    return d, length
