r"""Delta parts of a model (the ideal mirror), integrated exactly before any quadrature or sampling.

A part flagged ``BRDFFlags.DELTA`` (:class:`~lighting.models.mirror.Mirror`) sends all it reflects into
``R_v = 2 n (n·v) − v``; its ``eval`` is 0, so no rule with finitely many nodes sees it.  Its
integrals are closed forms instead:

    ρ(v)   = ∫ f_r (n·l) dω_l       = R(cos θ_v)
    L_o(v) = ∫ f_r L_i (n·l) dω_l   = R(cos θ_v) L_i(R_v)

with ``R`` the part's ``reflectance``.  The integrators split a model into its smooth remainder
(integrated as before) and its delta parts (added here, with zero error).
"""

from __future__ import annotations

import numpy as np

from ..models.base import BRDF, BRDFFlags, BRDFSum
from ..vec import reflect

__all__: list[str] = []

_N = np.array([0.0, 0.0, 1.0])  # the local frame's normal


class _DeltaSum:
    """Several delta parts at once: their reflectances add (they share the one direction ``R_v``)."""

    def __init__(self, parts):
        self.parts = tuple(parts)

    def _reflectance(self, c):
        return delta_albedo(self.parts, c)

    def reflectance(self, cos_theta):
        """``Σ_k R_k(cos θ)`` over the parts, shape ``(..., 3)`` (see :meth:`Mirror.reflectance`)."""
        with np.errstate(over="ignore"):  # saturates below: huge k_s of several parts may overflow
            total = sum(p.reflectance(cos_theta) for p in self.parts)
        return np.minimum(total, np.finfo(total.dtype).max)

    def __repr__(self):
        return " + ".join(repr(p) for p in self.parts)


def split_delta(brdf: BRDF):
    """``(smooth, deltas)``: the parts without a delta as one model (``None`` if there are none), the delta parts.

    A model without delta parts comes back as itself, so the smooth path is unchanged bit for bit.

    Parameters
    ----------
    brdf : BRDF
        A model or a sum of models.

    Returns
    -------
    smooth : BRDF or None
        The parts that are functions (one model or their sum); ``None`` if every part is a delta.
    deltas : tuple of BRDF
        The parts flagged ``BRDFFlags.DELTA``.
    """
    parts = brdf.parts
    deltas = tuple(p for p in parts if BRDFFlags.DELTA in p.flags)
    if not deltas:
        return brdf, ()
    smooth = [p for p in parts if BRDFFlags.DELTA not in p.flags]
    if not smooth:
        return None, deltas
    return (smooth[0] if len(smooth) == 1 else BRDFSum(*smooth)), deltas


def delta_albedo(deltas, cos_v: np.ndarray) -> np.ndarray:
    """``Σ R_k(cos θ_v)``: the fraction the delta parts reflect into the mirror direction.

    Parameters
    ----------
    deltas : sequence of BRDF
        Delta parts (each with ``_reflectance``).
    cos_v : numpy.ndarray
        float64 cosines ``n·v``, any shape ``(...)``.

    Returns
    -------
    numpy.ndarray
        float64 ``(..., 3)``; zeros without delta parts.
    """
    out = np.zeros(np.shape(cos_v) + (3,))
    with np.errstate(over="ignore"):  # huge k_s of several parts: inf here, saturated by the caller's _out
        for p in deltas:
            out = out + p._reflectance(cos_v)
    return out


def delta_radiance(deltas, env, vl: np.ndarray, to_world) -> np.ndarray:
    """``Σ R_k(cos θ_v) L_env(R_v)`` for local viewers ``vl`` ``(B, 3)``; ``to_world`` maps local ``(B, 1, 3)``.

    The environment is looked up only where some part reflects (a viewer above the horizon).

    Parameters
    ----------
    deltas : sequence of BRDF
        Delta parts.
    env : Environment
        The environment (``radiance(directions)`` in the world frame).
    vl : numpy.ndarray
        float64 local view directions ``(B, 3)`` (``n = ẑ``).
    to_world : callable
        Maps local directions ``(B, 1, 3)`` to the world frame.

    Returns
    -------
    numpy.ndarray
        float64 ``(B, 3)``: the delta parts' outgoing radiance.
    """
    out = np.zeros(vl.shape[:-1] + (3,))
    if not deltas:
        return out
    r = delta_albedo(deltas, vl[..., 2])
    lit = np.any(r != 0, axis=-1)
    if np.any(lit):
        # R_v in the local frame (n = ẑ), then in the world frame where the environment lives.
        d = to_world(reflect(vl, _N)[:, None, :])[:, 0, :]
        with np.errstate(over="ignore"):
            out[lit] = r[lit] * env._radiance(d[lit])
    return out
