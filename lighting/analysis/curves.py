r"""The BRDF against one angle: ``θ_h``, ``θ_d`` (half/difference angles) or the view angle.

Options (``cosine``, ``channel``, ``log``, ``dtype``) as in :mod:`lighting.analysis.quantity`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validate import check_bool, check_count
from . import _display
from .halfdiff import _above_horizon, half_diff_to_dirs
from .quantity import (
    _HALF_PI,
    _check_angle,
    _check_brdf,
    _check_channel,
    _check_cosine,
    _check_phi,
    _out_dtype,
    _plane_dirs,
    _sph,
)
from .slices import _slice_angles

__all__ = ["AngleCurve", "theta_h_curve", "theta_d_curve", "theta_v_curve"]


@dataclass(frozen=True, eq=False)
class AngleCurve:
    """A BRDF value plotted against one angle.

    Attributes
    ----------
    variable : str
        ``"theta_h"``, ``"theta_d"`` or ``"theta_v"``.
    angles : ndarray (n,)
        Abscissa in radians.
    values : ndarray (n, 3) or (n,)
        Plotted quantity; 0 where ``valid`` is False.
    l, v : ndarray (n, 3)
        The light and view directions of each sample.
    valid : ndarray (n,) bool
        Both directions strictly above the horizon.
    params : dict
        The fixed angles of the curve (e.g. ``{"theta_d": 0.0, "phi_d": π/2, "phi_h": 0.0}``).
    cosine, log, channel
        The options the curve was made with (``cosine`` normalized to ``None``, ``"light"`` or ``"view"``).
    model : str
        The model's short name (its one-line repr).

    Printed, a curve is one line with its key numbers; in a notebook it shows as a plot.
    """

    variable: str
    angles: np.ndarray
    values: np.ndarray
    l: np.ndarray  # noqa: E741 - the slides' name
    v: np.ndarray
    valid: np.ndarray
    params: dict
    cosine: str | None = None
    log: bool = False
    channel: object = None
    model: str = ""

    __repr__ = _display.curve_repr
    _repr_png_ = _display.curve_png


def _curve(brdf, variable, angles, l, v, cosine, log, channel, dt, params):  # noqa: E741
    """The :class:`AngleCurve` of the samples ``(l, v)`` (float64) at the abscissae ``angles``."""
    cos_mode = _check_cosine(cosine)
    log = check_bool("log", log)
    ch = _check_channel(channel, "rgb")
    values, valid = _above_horizon(brdf, l, v, cos_mode, log, ch, dt)
    return AngleCurve(variable, angles.astype(dt), values, l.astype(dt), v.astype(dt), valid, params, cos_mode, log,
                      channel, _display.model_label(brdf))  # fmt: skip


def theta_h_curve(
    brdf,
    theta_d=0.0,
    phi_d=_HALF_PI,
    *,
    phi_h=0.0,
    n=181,
    cosine=False,
    log=False,
    channel=None,
    dtype=None,
) -> AngleCurve:
    """The BRDF against the half angle ``θ_h ∈ [0, π/2]`` at fixed ``θ_d``, ``φ_d`` (and ``φ_h``).

    At ``θ_d = 0`` (the default) ``l = v = h``: the backscatter curve, whose shape is
    the specular lobe's NDF.  Samples are ``θ_h = π/2 · k/(n−1)``; where ``l`` or ``v``
    is not above the horizon the value is 0 and ``valid`` is False.

    Parameters
    ----------
    brdf : lighting.models.brdf.BRDF
        The model.
    theta_d : float
        Difference angle, in ``[0, π/2]``.
    phi_d, phi_h : float
        Azimuths of the difference vector and of the half vector.
    n : int
        Number of samples, 2 … 100001.
    cosine, log, channel, dtype
        See :mod:`lighting.analysis.quantity`.

    Returns
    -------
    AngleCurve
        ``variable="theta_h"``; ``params`` holds ``theta_d``, ``phi_d``, ``phi_h``.

    References
    ----------
    S. Rusinkiewicz, "A New Change of Variables for Efficient BRDF Representation", 1998.

    Examples
    --------
    >>> from lighting import BlinnPhong
    >>> c = theta_h_curve(BlinnPhong(1.0, 10, normalized=True), n=3, channel=0)
    >>> c.values.round(4).tolist()  # (e+2)/(2π) cos^e θ_h, 0 at the horizon
    [1.9099, 0.0597, 0.0]
    """
    _check_brdf(brdf)
    td = _check_angle("theta_d", theta_d, 0.0, _HALF_PI)
    pd, ph = _check_phi("phi_d", phi_d), _check_phi("phi_h", phi_h)
    count = check_count("n", n, 2, 100001)
    dt = _out_dtype(dtype, theta_d, phi_d)
    th = np.linspace(0.0, _HALF_PI, count)
    l, v = half_diff_to_dirs(th, ph, td, pd)  # noqa: E741
    params = {"theta_d": td, "phi_d": pd, "phi_h": ph}
    return _curve(brdf, "theta_h", th, l, v, cosine, log, channel, dt, params)


def theta_d_curve(
    brdf,
    theta_h=0.0,
    phi_d=_HALF_PI,
    *,
    phi_h=0.0,
    n=181,
    cosine=False,
    log=False,
    channel=None,
    dtype=None,
) -> AngleCurve:
    """The BRDF against the difference angle ``θ_d ∈ [0, π/2]`` at fixed ``θ_h``, ``φ_d`` (and ``φ_h``).

    At ``θ_h = 0`` (the default) ``h = n``: ``l`` and ``v`` are mirror images at
    ``θ_d`` from the normal, so the curve shows how the specular peak changes toward
    grazing (Fresnel, shadowing).  Samples ``θ_d = π/2 · k/(n−1)``; 0 and
    ``valid = False`` where ``l`` or ``v`` is not above the horizon.

    Parameters
    ----------
    brdf : lighting.models.brdf.BRDF
        The model.
    theta_h : float
        Half angle, in ``[0, π/2]``.
    phi_d, phi_h : float
        Azimuths of the difference vector and of the half vector.
    n : int
        Number of samples, 2 … 100001.
    cosine, log, channel, dtype
        See :mod:`lighting.analysis.quantity`.

    Returns
    -------
    AngleCurve
        ``variable="theta_d"``; ``params`` holds ``theta_h``, ``phi_d``, ``phi_h``.

    References
    ----------
    S. Rusinkiewicz, "A New Change of Variables for Efficient BRDF Representation", 1998.

    Examples
    --------
    >>> from lighting import Lambert
    >>> theta_d_curve(Lambert(1.0), n=3, channel=0).values.round(6).tolist()
    [0.31831, 0.31831, 0.0]
    """
    _check_brdf(brdf)
    th = _check_angle("theta_h", theta_h, 0.0, _HALF_PI)
    pd, ph = _check_phi("phi_d", phi_d), _check_phi("phi_h", phi_h)
    count = check_count("n", n, 2, 100001)
    dt = _out_dtype(dtype, theta_h, phi_d)
    td = np.linspace(0.0, _HALF_PI, count)
    l, v = half_diff_to_dirs(th, ph, td, pd)  # noqa: E741
    params = {"theta_h": th, "phi_d": pd, "phi_h": ph}
    return _curve(brdf, "theta_d", td, l, v, cosine, log, channel, dt, params)


def theta_v_curve(
    brdf,
    theta_l,
    *,
    phi_l=0.0,
    n=181,
    cosine=False,
    log=False,
    channel=None,
    refine=True,
    dtype=None,
) -> AngleCurve:
    """The BRDF against the view angle in the incidence plane, for a fixed light.

    The abscissa is the signed view angle ``θ_v ∈ [−π/2, π/2]`` of
    :func:`~lighting.analysis.slices.polar_slice` (``fixed="light"``): the light is at ``−theta_l`` and the
    mirror direction at ``+theta_l``; the ends are on the horizon (value 0).  This is
    the same data as the polar slice with the same ``n`` and ``refine``, drawn on
    Cartesian axes: with ``refine=True`` (default) the samples are the ``n`` uniform
    ones plus those where the lobe is, its peak included, so a highlight narrower than
    the grid or a hair above the horizon shows at the height
    :func:`~lighting.analysis.lobes.lobe_peak` finds.

    Parameters
    ----------
    brdf : lighting.models.brdf.BRDF
        The model.
    theta_l : float
        Polar angle of the light, in ``[0, π/2]``.
    phi_l : float
        Azimuth of the light (and of the plane of incidence).
    n : int
        Number of uniform samples, 2 … 100001.
    refine : bool
        Add the samples where the lobe is, as :func:`~lighting.analysis.slices.polar_slice` does.
    cosine, log, channel, dtype
        See :mod:`lighting.analysis.quantity`.

    Returns
    -------
    AngleCurve
        ``variable="theta_v"``; ``params`` holds ``theta_l`` and ``phi_l``.

    Examples
    --------
    >>> from lighting import Phong
    >>> c = theta_v_curve(Phong(1.0, 10), 0.3, n=181, channel=0)
    >>> float(c.angles[c.values.argmax()])  # the mirror direction, off the 1° grid, is a sample
    0.3
    >>> c = theta_v_curve(Phong(1.0, 10), 0.3, n=181, channel=0, refine=False)
    >>> round(float(c.angles[c.values.argmax()]), 4)  # the grid alone: the nearest degree
    0.2967
    """
    _check_brdf(brdf)
    theta = _check_angle("theta_l", theta_l, 0.0, _HALF_PI)
    phi = _check_phi("phi_l", phi_l)
    count = check_count("n", n, 2, 100001)
    refine = check_bool("refine", refine)
    cos_mode = _check_cosine(cosine)
    dt = _out_dtype(dtype, theta_l)
    t = _slice_angles(brdf, theta, phi, count, "incidence", refine, cos_mode, _check_channel(channel, "rgb"))
    v = _plane_dirs(t, phi, "incidence")
    l = np.broadcast_to(_sph(theta, phi), v.shape)  # noqa: E741
    return _curve(brdf, "theta_v", t, l, v, cosine, log, channel, dt, {"theta_l": theta, "phi_l": phi})
