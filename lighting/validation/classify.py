"""Classification of each engine value against its reference (normal, ill, edge, zero, over, under)."""

from __future__ import annotations

import numpy as np

from .cases import BOUND_FACTOR, unit_roundoff

# ============================================================================ classification
NORMAL, ILL, EDGE, ZERO, OVER, UNDER = range(6)
CLASSES = ("normal", "ill", "edge", "zero", "over", "under")


def _classify(hi, lo, nz, kappa, logref, edge, eng, dt):
    """Per point: class code, relative error, ratio, and whether the point passes.

    Arrays of any common shape ``S``; ``eng`` has shape ``S + (3,)`` (RGB: the worst
    channel counts).  Classes (:data:`CLASSES`):

    * ``normal`` — the true value is normal in the dtype: ``err <= 8 max(κ,1) u``;
    * ``ill`` — ``8 κ u >= 1``: the linear bound allows 100 % and no longer describes
      the error (``κ`` is the derivative of ``ln f``; a relative change ``κ u`` of 15
      means a factor ``e^15``), so the same first-order bound is applied to the
      logarithm: ``|ln(f_engine / f_true)| <= 8 κ u`` (or the test of its magnitude
      class below, whichever passes);
    * ``edge`` — a horizon or cone decision flips within ±8u: finite and >= 0 only;
    * ``zero`` — exactly 0 required;
    * ``over`` — beyond the largest finite value: exactly that value (saturation);
    * ``under`` — below the smallest normal: within ``8 κ u f`` plus the smallest normal.

    ``ratio`` is ``err / (max(κ,1) u)`` for normal points and ``|ln(f_e/f)| / (max(κ,1) u)``
    for ill ones (NaN elsewhere).
    """
    u = unit_roundoff(dt)
    fi = np.finfo(dt)
    tiny, big = float(fi.tiny), float(fi.max)
    k1 = np.where(np.isfinite(kappa), np.maximum(np.nan_to_num(kappa, nan=1.0), 1.0), np.inf)
    ref = hi + lo
    emax, emin = eng.max(axis=-1), eng.min(axis=-1)
    with np.errstate(invalid="ignore", over="ignore", divide="ignore"):
        diff = np.abs((eng - hi[..., None]) - lo[..., None]).max(axis=-1)
        err = np.where(ref > 0, diff / np.where(ref > 0, ref, 1.0), np.nan)
        ratio = err / (k1 * u)
        slack = BOUND_FACTOR * k1 * u
        logerr = np.abs(np.log(np.where(eng > 0, eng, 0)) - logref[..., None]).max(axis=-1)
        mag = np.where(ref < tiny, UNDER, np.where(ref > big, OVER, NORMAL))
        near = ref <= big * (1 + slack)
        ok_mag = np.where(
            mag == NORMAL,
            ratio <= BOUND_FACTOR,
            np.where(mag == UNDER, diff <= slack * ref + tiny, np.all(eng == big, axis=-1) | (near & (ratio <= 8))),
        )
        ok_ill = ok_mag | (logerr <= slack)
    cls = np.where(edge, EDGE, np.where(~nz, ZERO, np.where(slack >= 1, ILL, mag))).astype(np.int8)
    ok = np.select(
        [cls == EDGE, cls == ZERO, cls == ILL],
        [True, (emax == 0) & (emin == 0), ok_ill],
        default=ok_mag,
    )
    ok &= np.all(np.isfinite(eng), axis=-1) & (emin >= 0)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.where(cls == NORMAL, ratio, np.where(cls == ILL, logerr / (k1 * u), np.nan))
    err = np.where((cls == NORMAL) | (cls == ILL), err, np.nan)
    return cls, err, ratio, ok
