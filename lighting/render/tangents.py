r"""Surface tangents for anisotropic models: per vertex on meshes, per pixel after interpolation.

An anisotropic model (Ward, anisotropic GGX and Beckmann, Ashikhmin–Shirley, Disney's ``anisotropic``)
stretches its highlight along the surface tangent ``t`` it is given (``eval(n, l, v, tangent=t)``);
brushed metal is brushed along ``t``.  A mesh carries one unit tangent per vertex, perpendicular to
its normal, from one of three sources, in this order:

* **given** (a generator or the caller): the spheres of :mod:`lighting.render.mesh` take
  ``t = ∂p/∂φ / |∂p/∂φ|``, the direction of increasing longitude about their polar axis ``+y``
  (the camera's up), ``t = ŷ × n / |ŷ × n|``: a highlight stretched along ``t`` runs along the
  parallels, one stretched along ``b = n × t`` along the meridians;
* **from texture coordinates**: ``t ∝ ∂p/∂u`` of each triangle (the UV derivatives: with
  ``Δp₁ = p₁ − p₀``, ``Δp₂ = p₂ − p₀`` and ``Δu``, ``Δv`` likewise,
  ``∂p/∂u = (Δv₂ Δp₁ − Δv₁ Δp₂) / (Δu₁ Δv₂ − Δu₂ Δv₁)``), summed over the triangles around each
  vertex weighted by their interior angle there (as the normals are), then made perpendicular to the
  vertex normal (Gram–Schmidt: ``t − (n·t) n``) and normalized;
* **the default frame** otherwise: ``t = ẑ × n / |ẑ × n|`` and ``x̂`` where ``n`` is along ±z, the
  frame a model builds itself when it is given no tangent
  (:attr:`lighting.models.geometry.Geometry.t`: one convention, one home).

Where a source gives nothing (a sphere's poles, a vertex whose UVs are degenerate) the default frame
fills in.  Across a triangle the rasterizer interpolates the vertex tangents like the normals
(``Σ b_i t_i``) and re-orthonormalizes against the interpolated normal (:func:`orthonormal_tangents`);
near a sphere's pole the interpolated tangents turn through every direction (no smooth tangent field
covers a sphere), and an interpolated tangent that vanishes or lies along ``n`` takes the default frame.

Examples
--------
>>> t = sphere_tangents(np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]))
>>> t.tolist()  # ŷ × n on the sphere; at the pole n = ŷ the default frame's ẑ × n = −x̂
[[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [-1.0, 0.0, 0.0]]
"""

from __future__ import annotations

import numpy as np

from ..models.geometry import Geometry

__all__ = ["default_tangents", "sphere_tangents", "uv_tangents", "orthonormal_tangents"]


def default_tangents(normals) -> np.ndarray:
    """The default frame's tangent at each normal: ``ẑ × n / |ẑ × n|``, ``x̂`` where ``n`` is along ±z.

    Parameters
    ----------
    normals : numpy.ndarray, (..., 3)
        Unit (or zero) normals, float32 or float64.

    Returns
    -------
    numpy.ndarray, (..., 3)
        Unit tangents perpendicular to the normals, in their dtype: what a model uses without ``tangent=``.

    Examples
    --------
    >>> default_tangents(np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])).tolist()
    [[1.0, 0.0, 0.0], [-0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]
    """
    n = np.asarray(normals)
    dt = n.dtype.type if n.dtype.kind == "f" else np.float64
    return np.asarray(Geometry(n, n, n, unit=True, dtype=dt).t)


def orthonormal_tangents(tangents, normals) -> np.ndarray:
    """Tangents made unit and perpendicular to the normals: ``(t − (n·t) n) / |…|`` (Gram–Schmidt).

    Where that vanishes (a zero tangent, one along ``n``), the default frame (:func:`default_tangents`).

    Parameters
    ----------
    tangents : numpy.ndarray, (..., 3)
        Approximate tangents (interpolated ones are shorter than 1 and slightly off the surface).
    normals : numpy.ndarray, (..., 3)
        Unit (or zero) normals of the same shape and dtype.

    Returns
    -------
    numpy.ndarray, (..., 3)
        Unit tangents ``⊥ n``, in the dtype of ``normals``.

    Examples
    --------
    >>> orthonormal_tangents(np.array([[2.0, 0.0, 1.0]]), np.array([[0.0, 0.0, 1.0]])).tolist()
    [[1.0, 0.0, 0.0]]
    """
    n = np.asarray(normals)
    dt = n.dtype.type if n.dtype.kind == "f" else np.float64
    t = np.asarray(tangents, dtype=dt)
    # Geometry.t is the one home of this step: the given tangent made perpendicular to n, the default where it fails.
    return np.asarray(Geometry(n, n, n, unit=True, dtype=dt, tangent=t).t)


def sphere_tangents(unit_normals, axis=(0.0, 1.0, 0.0)) -> np.ndarray:
    """``∂p/∂φ`` on a sphere about ``axis``: ``axis × n / |axis × n|``; the default frame at the poles.

    Parameters
    ----------
    unit_normals : numpy.ndarray, (..., 3)
        Unit normals of the sphere (its points relative to the centre, divided by the radius).
    axis : 3-vector, default +y
        The polar axis (the spheres of :mod:`lighting.render.mesh` have their poles on ±y).

    Returns
    -------
    numpy.ndarray, (..., 3)
        Unit tangents along the parallels, in the dtype of ``unit_normals``.
    """
    n = np.asarray(unit_normals)
    dt = n.dtype.type if n.dtype.kind == "f" else np.float64
    return orthonormal_tangents(np.cross(np.asarray(axis, dtype=dt), n).astype(dt, copy=False), n)


def uv_tangents(vertices, faces, uvs, normals, corner_angles) -> np.ndarray:
    """Per-vertex tangents along ``∂p/∂u`` from texture coordinates (see the module notes).

    Parameters
    ----------
    vertices : numpy.ndarray, (V, 3)
    faces : numpy.ndarray of int, (F, 3)
    uvs : numpy.ndarray, (V, 2)
        Texture coordinates ``(u, v)`` per vertex.
    normals : numpy.ndarray, (V, 3)
        Unit vertex normals.
    corner_angles : numpy.ndarray, (F, 3)
        Interior angle of each triangle at each corner (the weights, as for the normals).

    Returns
    -------
    numpy.ndarray, (V, 3)
        Unit float64 tangents ``⊥ n``; the default frame where the UVs give no direction.
    """
    p = vertices[faces]
    w = uvs[faces]
    dp1, dp2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    du1, dv1 = w[:, 1, 0] - w[:, 0, 0], w[:, 1, 1] - w[:, 0, 1]
    du2, dv2 = w[:, 2, 0] - w[:, 0, 0], w[:, 2, 1] - w[:, 0, 1]
    det = du1 * dv2 - du2 * dv1
    # ∂p/∂u up to the factor 1/det, whose sign is kept (a mirrored chart flips t) and whose size is
    # dropped (each face's direction counts by its angle, not by how far its UVs are stretched).
    dpdu = (dv2[:, None] * dp1 - dv1[:, None] * dp2) * np.sign(det)[:, None]
    length = np.sqrt(np.einsum("ij,ij->i", dpdu, dpdu))
    with np.errstate(divide="ignore", invalid="ignore"):
        unit = np.where(length[:, None] > 0, dpdu / np.where(length > 0, length, 1.0)[:, None], 0.0)
    weighted = corner_angles[:, :, None] * unit[:, None, :]  # (F, 3 corners, 3)
    idx = faces.reshape(-1)
    flat = weighted.reshape(-1, 3)
    acc = np.stack([np.bincount(idx, weights=flat[:, c], minlength=len(vertices)) for c in range(3)], axis=1)
    return orthonormal_tangents(np.nan_to_num(acc), np.asarray(normals, dtype=np.float64))
