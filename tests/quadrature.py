"""Deterministic hemisphere quadrature used as an independent reference by the tests.

Composite Gauss–Legendre in θ on panels that grade geometrically toward the pole
(where narrow lobes live), and the periodic trapezoid rule in φ (spectrally
accurate for smooth periodic integrands).
"""

from __future__ import annotations

import numpy as np


def theta_nodes(lo=0.0, hi=np.pi / 2, *, scale=1e-3, panels=48, order=24):
    """Nodes and weights on [lo, hi], panels refined geometrically near ``lo``."""
    x, w = np.polynomial.legendre.leggauss(order)
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
    T, P = np.meshgrid(th, ph, indexing="ij")
    d = np.stack([np.sin(T) * np.cos(P), np.sin(T) * np.sin(P), np.cos(T)], -1)
    vals = np.asarray(func(d))
    w = (wt * np.sin(th))[:, None] * (2 * np.pi / n_phi)
    if vals.ndim == 3:
        w = w[..., None]
    return np.sum(vals * w, axis=(0, 1))


def direction(theta, phi=0.0):
    return np.array([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)])
