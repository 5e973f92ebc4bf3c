"""The model references' shading frame of exact inputs, made once per inputs and precision (a helper for tests).

:func:`lighting.validation.model_references.frame` depends on the directions (and the tangent) alone.  A test that
references a model at many parameter settings, or both ``f_r`` and ``f_r (n·l)``, at the same points reads the
same frame at each; made once, it is returned read-only, so no reference can change what the next one reads.
"""

from __future__ import annotations

import functools
import types

import mpmath

from lighting.validation import model_references as mr


def exact_frame(n, l, v, tangent=None):  # noqa: E741
    """``mr.frame(n, l, v, tangent)`` at the current mpmath precision, as a read-only mapping.

    ``n, l, v, tangent``: sequences of 3 floats (taken exactly) or mpf; ``tangent`` may be None.
    """
    return _frame(tuple(n), tuple(l), tuple(v), None if tangent is None else tuple(tangent), mpmath.mp.prec)


@functools.cache
def _frame(n, l, v, tangent, prec):  # noqa: E741
    with mpmath.mp.workprec(prec):
        return types.MappingProxyType(mr.frame(n, l, v, tangent))
