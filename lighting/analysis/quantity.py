r"""What every BRDF plot plots: the quantity, its options, and the checks of their arguments.

The decks plot a BRDF three ways: a *polar plot of reflectance strength* ("for one
view direction, showing light directions; for one light direction, showing view
directions"), a *2D slice* and a *3D surface*.  The modules of :mod:`lighting.analysis`
compute what those plots draw — angles, values, meshes — and never draw anything
themselves: the front end hands the arrays to Matplotlib or PyVista.

* :mod:`~lighting.analysis.slices` — polar slices and the reciprocity pair;
* :mod:`~lighting.analysis.halfdiff` — Rusinkiewicz's half/difference angles and the image over them;
* :mod:`~lighting.analysis.curves` — the BRDF against ``θ_h``, ``θ_d`` or the view angle;
* :mod:`~lighting.analysis.lobes` — a lobe's width and its peak;
* :mod:`~lighting.analysis.meshes` — the 3D lobe surface.

Frame and conventions
---------------------
Everything is in the local shading frame: the normal is ``n = +z``, ``theta`` is
measured from ``n`` and ``phi`` from ``+x`` toward ``+y`` (conventions.md).
Values are the physical BRDF ``f_r`` (1/sr) of ``brdf.eval``, zero on and below
the horizon.  Options shared by every function:

``cosine``
    ``False`` (default): ``f_r``.  ``True`` or ``"light"``: ``f_r (n·l)``, the
    integrand of the reflection equation (the explorer's "× n·l" toggle),
    computed by ``brdf.eval_cos`` without dividing by ``n·l``.  ``"view"``:
    ``f_r (n·v)``, the radiant intensity of the lit patch seen from ``v`` (a
    Lambertian surface then plots as the familiar cosine circle/sphere).
``channel``
    ``None``: RGB, shape ``(..., 3)`` (the 3D lobe, which needs one radius per
    vertex, uses luminance instead); ``0``/``1``/``2`` or ``"r"``/``"g"``/``"b"``:
    one channel; ``"luminance"``: ``Y = 0.2126 R + 0.7152 G + 0.0722 B``
    (Rec. 709 primaries of linear sRGB).
``log``
    ``True`` plots ``log10(1 + x)`` (computed as ``log1p(x)/ln 10``): zero stays
    zero, and a highlight a million times brighter than the diffuse floor still
    fits on the same axes.
``dtype``
    Output float type; by default the dtype of the angle/direction inputs
    (float64 for Python numbers, float32 for NumPy float32 inputs).  Directions are
    built in float64 and rounded once.

Every result is finite (no NaN, no Inf, no NumPy warning) for finite inputs,
including shininess 1e6, roughness 1e-6 and grazing incidence.
"""

from __future__ import annotations

import math

import numpy as np

from .._text import quote
from .._validate import ArgumentTypeError, check_float_dtype, real_array
from ..numerics import cos_sin, working_dtype
from ..vec import spherical_direction

__all__ = ["LUMINANCE"]

#: Rec. 709 luminance weights of linear sRGB: ``Y = 0.2126 R + 0.7152 G + 0.0722 B``.
LUMINANCE = (0.2126, 0.7152, 0.0722)

_HALF_PI = 0.5 * math.pi


# --------------------------------------------------------------------------- validation
# Every public function checks its arguments here, once: a wrong type raises ArgumentTypeError (a
# TypeError and a ValueError), a bad value ValueError, each naming the parameter, the value given
# (abbreviated) and what is allowed.
def _check_brdf(brdf):
    if not (callable(getattr(brdf, "eval", None)) and callable(getattr(brdf, "eval_cos", None))):
        raise ArgumentTypeError(
            f"brdf must be a reflectance model with eval and eval_cos (e.g. lighting.Lambert); "
            f"got {type(brdf).__name__} {quote(brdf)}"
        )
    return brdf


_COSINE_ALLOWED = "False, True, 'light' or 'view'"


def _check_cosine(cosine):
    if cosine is None or cosine is False or (isinstance(cosine, np.bool_) and not cosine):
        return None
    if cosine is True or isinstance(cosine, np.bool_):
        return "light"
    if isinstance(cosine, str):
        key = cosine.strip().lower()
        if key in ("light", "view"):
            return key
        raise ValueError(f"cosine must be {_COSINE_ALLOWED}; got {quote(cosine)}")
    raise ArgumentTypeError(f"cosine must be {_COSINE_ALLOWED}; got {type(cosine).__name__} {quote(cosine)}")


_CHANNEL_NAMES = {"r": 0, "red": 0, "g": 1, "green": 1, "b": 2, "blue": 2, "luminance": "luminance", "y": "luminance"}
_CHANNEL_ALLOWED = "None, 0, 1, 2, 'r', 'g', 'b' or 'luminance'"


def _check_channel(channel, default):
    if channel is None:
        return default
    if isinstance(channel, (int, np.integer)) and not isinstance(channel, (bool, np.bool_)):
        if 0 <= int(channel) <= 2:
            return int(channel)
        raise ValueError(f"channel must be {_CHANNEL_ALLOWED}; got {quote(channel)}")
    if isinstance(channel, str):
        if channel.strip().lower() in _CHANNEL_NAMES:
            return _CHANNEL_NAMES[channel.strip().lower()]
        raise ValueError(f"channel must be {_CHANNEL_ALLOWED}; got {quote(channel)}")
    raise ArgumentTypeError(f"channel must be {_CHANNEL_ALLOWED}; got {type(channel).__name__} {quote(channel)}")


def _scalar_angle(name, value, allowed):
    arr = real_array(name, value, allowed=allowed, dtype=np.float64)
    if arr.ndim != 0:
        raise ValueError(f"{name} must be {allowed}, a scalar; got shape {arr.shape}: {quote(value)}")
    return float(arr)


def _check_angle(name, value, lo, hi):
    """A finite scalar angle in ``[lo, hi]``; float32 roundings of the ends (1e-6 rad) are clamped."""
    allowed = f"a finite angle in radians in [{lo:g}, {hi:g}]"
    x = _scalar_angle(name, value, allowed)
    if not lo - 1e-6 <= x <= hi + 1e-6:
        raise ValueError(f"{name} must be {allowed}; got {quote(value)}")
    return min(max(x, lo), hi)


def _check_phi(name, value):
    return _scalar_angle(name, value, "a finite angle in radians")


def _check_tangent(tangent):
    """``None``, or a unit tangent (float64, shape (3,)) in the plane ``z = 0`` of the local frame.

    The tangent ``t`` orients anisotropic lobes (``α_x`` along ``t``, ``α_y`` along ``b = n × t``); only its
    part perpendicular to ``n = +z`` counts, so that part must not vanish.
    """
    if tangent is None:
        return None
    allowed = "None or a direction (3,) not along the normal n = +z"
    arr = real_array("tangent", tangent, allowed=allowed, dtype=np.float64)
    if arr.shape != (3,):
        raise ValueError(f"tangent must be {allowed}; got shape {arr.shape}: {quote(tangent)}")
    t = np.array([arr[0], arr[1], 0.0])
    size = math.hypot(t[0], t[1])
    if not size > 0 or not math.isfinite(size):
        raise ValueError(f"tangent must be {allowed}; got {quote(tangent)}")
    return t / size


def _out_dtype(dtype, *inputs):
    return working_dtype(*inputs) if dtype is None else check_float_dtype(dtype).type


# --------------------------------------------------------------------------- evaluation
def _quantity_rgb(brdf, l, v, cosine, dt, tangent=None):  # noqa: E741
    """The plotted RGB quantity for unit ``l``, ``v`` (float64 arrays), in dtype ``dt``.

    ``tangent`` (checked by :func:`_check_tangent`) orients an anisotropic lobe; ``None`` leaves the
    models' documented default, which at ``n = +z`` is ``t = +x``.
    """
    n = np.array([0.0, 0.0, 1.0], dtype=dt)
    l, v = np.asarray(l, dt), np.asarray(v, dt)  # noqa: E741
    frame = {} if tangent is None else {"tangent": np.asarray(tangent, dt)}
    if cosine == "light":
        f = brdf.eval_cos(n, l, v, **frame)
    else:
        f = brdf.eval(n, l, v, **frame)
        if cosine == "view":
            f = f * np.maximum(v[..., 2], 0)[..., None]
    return np.asarray(f, dtype=dt)


def _reduce(rgb, channel):
    if channel == "rgb":
        return rgb
    if channel == "luminance":
        w = np.asarray(LUMINANCE, dtype=rgb.dtype)
        return rgb[..., 0] * w[0] + rgb[..., 1] * w[1] + rgb[..., 2] * w[2]
    return rgb[..., channel]


def _log_scale(x, log):
    if not log:
        return x
    return (np.log1p(x) / x.dtype.type(math.log(10))).astype(x.dtype, copy=False)


def _plane_dirs(t, phi, plane):
    """Unit directions (float64) at signed angle ``t`` across a plane through ``n``.

    Built through :func:`lighting.numerics.cos_sin`, like every direction of this module, so
    ``|t| = π/2`` lands exactly on the horizon (z = 0), where every BRDF is 0.
    """
    c, s = cos_sin(np.asarray(t, dtype=np.float64))
    cp, sp = cos_sin(float(phi))
    if plane == "incidence":
        ax, ay = -cp, -sp  # positive t: away from the fixed direction's azimuth
    else:
        ax, ay = -sp, cp  # positive t: toward azimuth phi + π/2
    return np.stack(np.broadcast_arrays(s * ax, s * ay, c), axis=-1) + 0.0  # + 0.0: no signed zeros


def _sph(theta, phi):
    """Unit direction (float64) at polar angle ``theta``: :func:`lighting.vec.spherical_direction`.

    ``theta = π/2`` lies exactly on the horizon (z = 0), not at ``cos(π/2) = 6e-17`` above it,
    where the slides' Phong BRDF divides by it.
    """
    return spherical_direction(float(theta), float(phi), dtype=np.float64)
