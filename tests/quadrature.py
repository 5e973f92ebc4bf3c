"""Deterministic hemisphere quadrature used as an independent reference by the tests.

Composite Gauss–Legendre in θ on panels that grade geometrically toward the pole
(where narrow lobes live), and the periodic trapezoid rule in φ (spectrally
accurate for smooth periodic integrands).
"""

from __future__ import annotations

import functools
import math

import numpy as np


@functools.cache
def leggauss(order):
    """``numpy.polynomial.legendre.leggauss(order)``, computed once per order (read-only arrays).

    NumPy finds the nodes as the eigenvalues of a dense ``order × order`` matrix, which dominates a test
    that asks for the same high-order rule again and again; the cached arrays are the very same numbers.
    """
    x, w = np.polynomial.legendre.leggauss(order)
    x.flags.writeable = False
    w.flags.writeable = False
    return x, w


def evaluate(func, points, block=1 << 14):
    """``func(points)`` for ``(..., 3)`` points, evaluated in blocks of ``block`` points.

    The same values as one call (``func`` acts point by point), with the temporaries of each block small
    enough to stay in the processor's cache instead of streaming arrays of millions of points.
    """
    flat = points.reshape(-1, points.shape[-1])
    parts = [np.asarray(func(flat[i : i + block])) for i in range(0, len(flat), block)]
    out = np.concatenate(parts)
    return out.reshape(points.shape[:-1] + out.shape[1:])


def theta_nodes(lo=0.0, hi=np.pi / 2, *, scale=1e-3, panels=48, order=24):
    """Nodes and weights on [lo, hi], panels refined geometrically near ``lo``."""
    x, w = leggauss(order)
    edges = np.concatenate([[lo], lo + np.geomspace(scale, hi - lo, panels)])
    nodes, weights = [], []
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        nodes.append(0.5 * (b - a) * x + 0.5 * (b + a))
        weights.append(0.5 * (b - a) * w)
    return np.concatenate(nodes), np.concatenate(weights)


def hemisphere(func, *, scale=1e-3, panels=48, order=24, n_phi=256):
    """∫_Ω func(l) dω_l over the upper hemisphere; ``func`` takes ``(..., 3)`` directions."""
    th, wt = theta_nodes(scale=scale, panels=panels, order=order)
    ph = (np.arange(n_phi) + 0.5) * (2 * np.pi / n_phi)
    # The directions of the (θ, φ) grid, each sine and cosine taken once per θ and once per φ (the same numbers as
    # taken at every node of the grid): one pass per component, written into the stacked array.
    d = np.empty((len(th), n_phi, 3))
    st = np.sin(th)[:, None]
    np.multiply(st, np.cos(ph), out=d[..., 0])
    np.multiply(st, np.sin(ph), out=d[..., 1])
    d[..., 2] = np.cos(th)[:, None]
    vals = evaluate(func, d)
    w = (wt * np.sin(th))[:, None] * (2 * np.pi / n_phi)
    if vals.ndim == 3:
        w = w[..., None]
    return np.sum(vals * w, axis=(0, 1))


def direction(theta, phi=0.0):
    return np.array([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)])


def half_vector_integral(func, alpha, v=None):
    """``∫ func(h) dω_h`` over the upper hemisphere; with ``v``, over the arc of φ where ``v·h > 0``.

    θ_h in Gauss–Legendre panels graded toward the pole by ``alpha`` (60 × 24 nodes); φ by the periodic trapezoid
    rule (1024 nodes) over the whole circle, or Gauss–Legendre (384 nodes) over the arc where ``v·h > 0`` (the
    integrand's kink there an endpoint).
    """
    nodes = half_vector_nodes(alpha, v)
    return half_vector_sum(evaluate(func, nodes[0]), nodes)


def half_vector_sum(values, nodes):
    """:func:`half_vector_integral`'s sum of ``values`` already evaluated at ``nodes`` (:func:`half_vector_nodes`):
    for several integrands that share one factor, evaluated once on the same nodes."""
    _, half, w, th, wt = nodes
    return float(np.sum(values * half[:, None] * w * (wt * np.sin(th))[:, None]))


def half_vector_nodes(alpha, v=None):
    """The nodes ``h`` of :func:`half_vector_integral` and the factors of its weights: ``(h, half, w, θ, w_θ)``."""
    th, wt = theta_nodes(scale=alpha * 1e-3, panels=60, order=24)
    if v is None or v[2] >= 1:
        half, pv = np.full(th.shape, math.pi), 0.0
        x, w = np.arange(1024) / 512 - 1, np.full(1024, 2 / 1024)
        # Every ring spans the whole circle: its azimuths are one row, whose sines and cosines each ring shares.
        ph = pv + half[:1, None] * x
    else:
        tv, pv = math.acos(v[2]), math.atan2(v[1], v[0])
        half = np.arccos(np.clip(-math.cos(tv) * np.cos(th) / (math.sin(tv) * np.sin(th)), -1, 1))
        x, w = leggauss(384)
        ph = pv + half[:, None] * x
    h = np.stack(
        np.broadcast_arrays(np.sin(th)[:, None] * np.cos(ph), np.sin(th)[:, None] * np.sin(ph), np.cos(th)[:, None]),
        -1,
    )
    return h, half, w, th, wt
