"""The engine side of the stability sweep: the values the engine computes on the cases."""

from __future__ import annotations

import numpy as np

from .cases import LIGHT_FORMS


# ============================================================================ engine side
def _engine_brdf(specs, cols, n, l, v):  # noqa: E741
    """Engine values ``(m, len(cols), 3)`` (float64 copies), reciprocal ``eval(n, v, l)`` per column, warnings.

    ``model.eval(n, l, v)`` is ``model.eval_geometry(Geometry(n, l, v))`` (likewise for
    ``eval_cos`` and ``classic``); one :class:`~lighting.models.brdf.Geometry` is shared by every
    model, which is what a shading pass does too.
    """
    import warnings

    from ..models.brdf import Geometry

    m = n.shape[0]
    vals = np.zeros((m, len(cols), 3))
    swapped = {}
    method = {"eval": "eval_geometry", "eval_cos": "eval_cos_geometry", "classic": "classic_geometry"}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        g, gs = Geometry(n, l, v), Geometry(n, v, l)
        for c, (si, form) in enumerate(cols):
            model = specs[si].model
            out = model.D(g)[:, None] if form == "D" else getattr(model, method[form])(g)
            vals[:, c, :] = np.broadcast_to(out, (m, 3))
            if form == "eval" and specs[si].reciprocal:
                swapped[c] = model.eval_geometry(gs).astype(np.float64)
    return vals, swapped, len(caught)


def _engine_brdf_stacked(specs, cols, n, l, v, eng):  # noqa: E741
    """The image path's values: ``separable_cos`` / ``separable_classic`` on a stacked geometry.

    A renderer lights all directional lights of a frame at once through a
    ``StackedGeometry``; here the ``m`` light directions of the cases are stacked
    over the ``m`` points (an ``(m, m)`` geometry) and the diagonal, case ``i``'s
    own light at its own point, is compared.  Columns the image path does not
    take (``eval``, ``D``, models that do not stack) keep the values of ``eng``.
    Returns the values and the number of warnings.
    """
    import warnings

    from ..shading.separable import stacks
    from ..shading.stacked import StackedGeometry
    from ..vec import normalize

    out = eng.copy()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        g = StackedGeometry(normalize(n), normalize(l), normalize(v))
        idx = np.arange(n.shape[0])
        for c, (si, form) in enumerate(cols):
            model = specs[si].model
            if form not in ("eval_cos", "classic") or not all(stacks(p) for p in model.parts):
                continue
            fields = model.separable_cos(g) if form == "eval_cos" else model.separable_classic(g)
            with np.errstate(over="ignore"):
                vals = sum(
                    np.broadcast_to(f, (len(idx), len(idx)))[idx, idx].astype(np.float64)[:, None] * col
                    for f, col in fields
                )
            out[:, c, :] = np.minimum(vals, float(np.finfo(n.dtype).max))
    return out, len(caught)


def _engine_light(specs, cases, dt):
    import warnings

    m = len(cases)
    vals = np.zeros((m, len(LIGHT_FORMS), 3))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for si in sorted({c.spec for c in cases}):
            idx = [i for i, c in enumerate(cases) if c.spec == si]
            pts = np.array([cases[i].point for i in idx], dtype=dt)
            inc = next(specs[si].light.incident(pts, dtype=dt))
            vals[idx, 0, :] = np.asarray(inc.scale, dtype=np.float64)[:, None]
            vals[idx, 1, :] = np.broadcast_to(np.asarray(inc.irradiance, dtype=np.float64), (len(idx), 3))
    return vals, len(caught)
