r"""Rusinkiewicz's half/difference angles, and the BRDF as an image over them.

A direction pair ``(l, v)`` is described by its half vector ``h = (l + v)/|l + v|``
(angles ``θ_h``, ``φ_h``) and the *difference* vector, ``l`` seen from a frame whose pole
is ``h`` (angles ``θ_d``, ``φ_d``).  Specular lobes then lie along ``θ_h`` and Fresnel and
shadowing effects along ``θ_d``; isotropic BRDFs do not depend on ``φ_h``.  Options
(``cosine``, ``channel``, ``log``, ``dtype``) as in :mod:`lighting.analysis.quantity`.

References
----------
S. Rusinkiewicz, "A New Change of Variables for Efficient BRDF Representation",
Rendering Techniques '98 (Eurographics Workshop on Rendering), 1998.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validate import check_bool, check_choice, check_count, check_vectors, real_array
from ..numerics import cos_sin, safe_div, working_dtype
from ..vec import halfway, normalize
from . import _display
from .quantity import (
    _HALF_PI,
    _check_brdf,
    _check_channel,
    _check_cosine,
    _check_phi,
    _log_scale,
    _out_dtype,
    _quantity_rgb,
    _reduce,
)

__all__ = ["HalfDiffImage", "half_diff_to_dirs", "dirs_to_half_diff", "half_diff_image"]

#: Half/difference-angle samples with ``|z|`` below this are on the horizon.  Directions built
#: from angles are exact there (:func:`lighting.numerics.cos_sin`), but the two rotations of
#: :func:`half_diff_to_dirs` round each component by a few ulp: at ``φ_d = 0`` a pair with
#: ``θ_h + θ_d = π/2`` would otherwise land a rounding error above the horizon, where the
#: slides' Phong BRDF (``1/(n·l)``) is ~1e16.  Eight ulp of 1 bound that rounding.
_HORIZON_TOL = 8 * float(np.finfo(np.float64).eps)


def _rot_y(x, y, z, c, s):
    """Rotation about +y by the angle with cosine ``c`` and sine ``s`` (takes +z toward +x)."""
    return x * c + z * s, y, z * c - x * s


def _rot_z(x, y, z, c, s):
    return x * c - y * s, x * s + y * c, z


def half_diff_to_dirs(theta_h, phi_h, theta_d, phi_d):
    r"""Light and view directions from Rusinkiewicz's half/difference angles.

    Rusinkiewicz, "A New Change of Variables for Efficient BRDF Representation"
    (EGWR 1998): the half vector ``h`` has spherical angles ``(θ_h, φ_h)``; the
    *difference* vector ``d`` is ``l`` seen from a frame whose pole is ``h``,
    ``d = rot_y(−θ_h) rot_z(−φ_h) l``, with spherical angles ``(θ_d, φ_d)``.  Hence:

        l = rot_z(φ_h) rot_y(θ_h) (sin θ_d cos φ_d, sin θ_d sin φ_d, cos θ_d)
        v = rot_z(φ_h) rot_y(θ_h) (−sin θ_d cos φ_d, −sin θ_d sin φ_d, cos θ_d)

    (``v`` is ``d`` mirrored about the pole ``h``), so ``h = (l + v)/|l + v|`` and
    ``cos θ_d = l·h = v·h``.  ``rot_y(θ)`` tips ``+z`` toward ``+x``.  Isotropic BRDFs
    do not depend on ``φ_h``.

    Parameters
    ----------
    theta_h, phi_h, theta_d, phi_d : array_like
        Angles in radians; they broadcast together.

    Returns
    -------
    l, v : ndarray (..., 3)
        Unit vectors (possibly below the horizon: no masking here), float dtype of the inputs.

    References
    ----------
    S. Rusinkiewicz, "A New Change of Variables for Efficient BRDF Representation",
    Rendering Techniques '98 (Eurographics Workshop on Rendering), 1998.

    Examples
    --------
    >>> l, v = half_diff_to_dirs(0.0, 0.0, 0.5, 0.0)  # h = n: l and v mirror each other
    >>> l.round(4).tolist(), v.round(4).tolist()
    ([0.4794, 0.0, 0.8776], [-0.4794, -0.0, 0.8776])
    """
    names = ("theta_h", "phi_h", "theta_d", "phi_d")
    given = [real_array(k, a, allowed="finite angles in radians")
             for k, a in zip(names, (theta_h, phi_h, theta_d, phi_d), strict=True)]  # fmt: skip
    dt = working_dtype(theta_h, phi_h, theta_d, phi_d)  # Python numbers are weak: the arrays decide
    try:
        th, ph, td, pd = np.broadcast_arrays(*(a.astype(np.float64) for a in given))
    except ValueError:
        shapes = ", ".join(f"{k} {a.shape}" for k, a in zip(names, given, strict=True))
        raise ValueError(f"theta_h, phi_h, theta_d and phi_d must broadcast together; got shapes {shapes}") from None
    ct, st = cos_sin(td)  # exact at right angles: θ_d = π/2 with φ_d = π/2 is exactly on the horizon
    cpd, spd = cos_sin(pd)
    dx, dy, dz = st * cpd, st * spd, ct
    ch, sh = cos_sin(th)
    cp, sp = cos_sin(ph)
    out = []
    for x, y in ((dx, dy), (-dx, -dy)):
        a = _rot_z(*_rot_y(x, y, dz, ch, sh), cp, sp)
        out.append(np.stack(a, axis=-1).astype(dt))
    return out[0], out[1]


def dirs_to_half_diff(l, v):  # noqa: E741
    r"""Rusinkiewicz's half/difference angles ``(θ_h, φ_h, θ_d, φ_d)`` of direction pairs.

    The inverse of :func:`half_diff_to_dirs`:
    ``h = (l + v)/|l + v|``, ``θ_h = atan2(|h_xy|, h_z)``, ``φ_h = atan2(h_y, h_x)``,
    ``d = rot_y(−θ_h) rot_z(−φ_h) l``, ``θ_d = atan2(|d_xy|, d_z)``, ``φ_d = atan2(d_y, d_x)``.
    Angles come from ``atan2`` (accurate at 0 and π/2, unlike ``arccos``); ``φ`` lies in
    ``(−π, π]``.  Where an angle is undefined (``φ_h`` at ``θ_h = 0``, ``φ_d`` at
    ``θ_d = 0``) it is 0; ``l = −v`` (no half vector) gives ``θ_h = φ_h = 0`` and the angles of ``l``.

    Parameters
    ----------
    l, v : array_like (..., 3)
        Directions (normalized on entry); they broadcast together.

    Returns
    -------
    theta_h, phi_h, theta_d, phi_d : ndarray (...)
        Float dtype of the inputs.

    References
    ----------
    S. Rusinkiewicz, "A New Change of Variables for Efficient BRDF Representation",
    Rendering Techniques '98 (Eurographics Workshop on Rendering), 1998.

    Examples
    --------
    >>> [round(float(a), 6) for a in dirs_to_half_diff((0.6, 0.0, 0.8), (-0.6, 0.0, 0.8))]
    [0.0, 0.0, 0.643501, 0.0]
    """
    allowed = "finite real vectors of shape (..., 3)"
    dt = working_dtype(l, v)
    l, v = real_array("l", l, allowed=allowed), real_array("v", v, allowed=allowed)  # noqa: E741
    if l.shape[-1:] != (3,) or v.shape[-1:] != (3,):
        raise ValueError(f"l and v must be {allowed}; got shapes {l.shape} and {v.shape}")
    l, v = check_vectors("l", l, nonzero=True), check_vectors("v", v, nonzero=True)  # noqa: E741
    try:
        np.broadcast_shapes(l.shape, v.shape)
    except ValueError:
        raise ValueError(f"l and v must broadcast together; got shapes {l.shape} and {v.shape}") from None
    a, b = normalize(l.astype(np.float64)), normalize(v.astype(np.float64))
    a, b = np.broadcast_arrays(a, b)
    h = halfway(a, b)
    theta_h = np.arctan2(np.hypot(h[..., 0], h[..., 1]), h[..., 2])
    phi_h = np.arctan2(h[..., 1], h[..., 0])
    # Build the rotations from h's components directly (no trig round trip).
    rxy = np.hypot(h[..., 0], h[..., 1])
    safe = rxy > 0
    cp = np.where(safe, safe_div(h[..., 0], rxy), 1.0)  # φ_h = 0 where it is undefined
    sp = safe_div(h[..., 1], rxy)
    x, y, z = _rot_z(a[..., 0], a[..., 1], a[..., 2], cp, -sp)
    degenerate = ~np.any(h != 0, axis=-1)
    ch = np.where(degenerate, 1.0, h[..., 2])
    x, y, z = _rot_y(x, y, z, ch, -rxy)
    theta_d = np.arctan2(np.hypot(x, y), z)
    phi_d = np.arctan2(y, x)
    return tuple(q.astype(dt) for q in (theta_h, phi_h, theta_d, phi_d))


def _above_horizon(brdf, l, v, cos_mode, log, ch, dt):  # noqa: E741
    """``(values, valid)``: the plotted quantity where ``l`` and ``v`` are both above the horizon, 0 elsewhere.

    ``valid`` is ``l_z > tol`` and ``v_z > tol`` (``_HORIZON_TOL``); the options are already checked.
    """
    valid = (l[..., 2] > _HORIZON_TOL) & (v[..., 2] > _HORIZON_TOL)
    rgb = _quantity_rgb(brdf, l, v, cos_mode, dt)
    rgb = np.where(valid[..., None], rgb, 0).astype(dt, copy=False)
    return _log_scale(_reduce(rgb, ch), log), valid


@dataclass(frozen=True, eq=False)
class HalfDiffImage:
    """A BRDF over the half/difference angles ``(θ_h, θ_d)`` at fixed ``φ_d`` (and ``φ_h``).

    ``values[i, j]`` is at ``theta_d[i]``, ``theta_h[j]``: **rows are θ_d, columns θ_h**
    (``imshow(values, origin="lower")`` puts ``θ_h`` on the horizontal axis and ``θ_d``
    upward, the usual layout).  Where ``l`` or ``v`` is on or below the horizon the
    value is 0 and ``valid`` is False; there are no NaNs.  ``cosine``, ``log`` and ``channel`` are the
    options it was made with, ``model`` the model's short name (its one-line repr).

    Printed, the image is one line with its size and range; in a notebook it shows as a picture,
    :meth:`srgb8` enlarged by a whole factor until its longer side has at least 256 pixels.
    """

    theta_h: np.ndarray  # (n_h,)
    theta_d: np.ndarray  # (n_d,)
    values: np.ndarray  # (n_d, n_h, 3) or (n_d, n_h)
    valid: np.ndarray  # (n_d, n_h) bool
    phi_d: float
    phi_h: float
    cosine: str | None = None
    log: bool = False
    channel: object = None
    model: str = ""

    __repr__ = _display.image_repr

    def srgb8(self) -> np.ndarray:
        """The image as 8-bit sRGB pixels, one per sample, ``θ_h`` to the right and ``θ_d`` upward.

        The values are divided by the 99th percentile of the valid ones (RGB channels together, so
        colours keep their ratios; the largest value if that percentile is 0), so that a blow-up at
        grazing angles does not leave the rest black, and sRGB-encoded
        (:func:`lighting.render.image.encode_srgb8`, brighter values clip to white); one channel shows
        grey.  Samples with no value (``valid`` False: a direction on or below the horizon) are a muted
        blue, ``(72, 88, 120)``.

        Returns
        -------
        numpy.ndarray, (n_d, n_h, 3), uint8
            Row 0 (the top) is ``θ_d = theta_d[-1]``.
        """
        return _display.image_srgb8(self.values, self.valid)

    def _repr_png_(self):
        """The picture in a notebook: :meth:`srgb8`, each pixel a square block, as PNG bytes."""
        return _display.image_png(self.srgb8())


def half_diff_image(
    brdf,
    phi_d=_HALF_PI,
    n_h=91,
    n_d=91,
    *,
    phi_h=0.0,
    theta_h_spacing="uniform",
    cosine=False,
    log=False,
    channel=None,
    dtype=None,
) -> HalfDiffImage:
    r"""The BRDF as an image over ``(θ_h, θ_d) ∈ [0, π/2]²`` at fixed ``φ_d`` — rows θ_d, columns θ_h.

    The usual "image slice" of BRDF tools: with the default ``φ_d = π/2`` both ``l``
    and ``v`` have ``z = cos θ_h cos θ_d``, so the whole open square is above the
    horizon; with ``φ_d = 0`` only ``θ_h + θ_d < π/2`` is.  Pixels where ``l`` or ``v``
    is on or below the horizon hold 0 and ``valid`` is False (no NaN).

    ``theta_h_spacing="sqrt"`` samples ``θ_h = π/2 · u²`` (``u`` uniform), the
    spacing of tabulated measured BRDFs, which puts more columns into the specular
    peak near ``θ_h = 0``; ``"uniform"`` samples ``θ_h = π/2 · u``.  ``θ_d`` is
    always uniform.  Axes include both ends.

    Parameters
    ----------
    brdf : lighting.models.brdf.BRDF
        The model.
    phi_d : float
        Azimuth of the difference vector (default ``π/2``).
    n_h, n_d : int
        Columns and rows, 2 … 4096 each.
    phi_h : float
        Azimuth of the half vector (isotropic models do not depend on it).
    theta_h_spacing : {"uniform", "sqrt"}
        Spacing of the columns.
    cosine, log, channel, dtype
        See :mod:`lighting.analysis.quantity`.

    Returns
    -------
    HalfDiffImage
        The axes ``theta_h`` (columns) and ``theta_d`` (rows), ``values`` and ``valid``.

    References
    ----------
    S. Rusinkiewicz, "A New Change of Variables for Efficient BRDF Representation",
    Rendering Techniques '98 (Eurographics Workshop on Rendering), 1998.

    Examples
    --------
    >>> from lighting import Lambert
    >>> im = half_diff_image(Lambert(1.0), phi_d=0.0, n_h=3, n_d=3, channel=0)
    >>> im.valid.tolist()  # rows θ_d = 0, π/4, π/2; columns θ_h = 0, π/4, π/2
    [[True, True, False], [True, False, False], [False, False, False]]
    """
    _check_brdf(brdf)
    pd, ph = _check_phi("phi_d", phi_d), _check_phi("phi_h", phi_h)
    nh = check_count("n_h", n_h, 2, 4096)
    nd = check_count("n_d", n_d, 2, 4096)
    spacing = check_choice("theta_h_spacing", theta_h_spacing, ("uniform", "sqrt"))
    cos_mode = _check_cosine(cosine)
    log = check_bool("log", log)
    ch = _check_channel(channel, "rgb")
    dt = _out_dtype(dtype, phi_d)
    th = np.linspace(0.0, _HALF_PI, nh)
    if spacing == "sqrt":
        th = _HALF_PI * np.linspace(0.0, 1.0, nh) ** 2
    td = np.linspace(0.0, _HALF_PI, nd)
    l, v = half_diff_to_dirs(th[None, :], ph, td[:, None], pd)  # noqa: E741
    values, valid = _above_horizon(brdf, l, v, cos_mode, log, ch, dt)
    return HalfDiffImage(th.astype(dt), td.astype(dt), values, valid, pd, ph, cos_mode, log, channel,
                         _display.model_label(brdf))  # fmt: skip
