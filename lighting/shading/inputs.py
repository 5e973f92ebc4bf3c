"""Checked inputs of the illumination equation: lights, terms, options, view vectors.

Every argument of :func:`~lighting.shading.equation.shade` is checked here once
(:func:`prepare`), so the reference loop, the fast path and the renderer share
one set of checks and one computation of the slides' ``v``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from .._text import quote
from .._validate import ArgumentTypeError, check_choice, check_vectors
from ..lights.punctual import AmbientLight, DirectionalLight, Light
from ..numerics import as_float, working_dtype
from ..vec import length, normalize
from .material import check_material

__all__ = ["TERMS", "FORMS", "ShadeOptions", "Samples", "view_vectors", "check_lights", "check_terms", "prepare",
           "prepare_tangents"]  # fmt: skip

TERMS = ("emission", "ambient", "diffuse", "specular")
FORMS = ("classic", "physical")


def check_lights(lights, name: str = "lights") -> list:
    """``lights`` as a list of lights (ambient, directional, point, spot, area); O(number of lights).

    Parameters
    ----------
    lights : sequence of lights
    name : str
        The argument's name in error messages.

    Returns
    -------
    list
        The lights, in order.
    """
    if isinstance(lights, (Light, AmbientLight)):
        raise ArgumentTypeError(f"{name} must be a sequence of lights; got a single {type(lights).__name__}: "
                                f"{quote(lights)} (wrap it in a list)")  # fmt: skip
    if isinstance(lights, (str, bytes, dict)) or not hasattr(lights, "__iter__"):
        raise ArgumentTypeError(f"{name} must be a sequence of lights (AmbientLight, DirectionalLight, ...); "
                                f"got {type(lights).__name__} {quote(lights)}")  # fmt: skip
    out = list(lights)
    for i, lt in enumerate(out):
        if not isinstance(lt, (Light, AmbientLight)):
            raise ArgumentTypeError(f"{name}[{i}] must be a light (AmbientLight, DirectionalLight, PointLight, "
                                    f"SpotLight, RectLight, DiskLight); got {type(lt).__name__} "
                                    f"{quote(lt)}")  # fmt: skip
    return out


def points_needed_error(light) -> ArgumentTypeError:
    """The error for ``points=None`` with a ``light`` that needs the surface positions.

    Parameters
    ----------
    light : Light
        The first light that needs them (named in the message).

    Returns
    -------
    ArgumentTypeError
        To be raised by the caller.
    """
    i = type(light).__name__
    return ArgumentTypeError(f"points=None is allowed only for ambient and directional lights; {i} needs the "
                             f"surface positions (points: finite real vectors of shape (..., 3)): {quote(light)}")


def positional_lights(lights) -> list:
    """The lights that depend on where the surface point is (all but ambient and directional ones).

    Parameters
    ----------
    lights : list of lights

    Returns
    -------
    list
        Those lights, in order.
    """
    return [lt for lt in lights if not isinstance(lt, (AmbientLight, DirectionalLight))]


def check_terms(terms) -> list:
    """``terms`` as a list of term names; a string, a mapping or a set is refused (order and kind matter).

    Parameters
    ----------
    terms : sequence of {"emission", "ambient", "diffuse", "specular"}

    Returns
    -------
    list of str
    """
    if isinstance(terms, (str, bytes, dict, set, frozenset)) or not hasattr(terms, "__iter__"):
        raise ArgumentTypeError(f"terms must be a sequence of names from {TERMS}; got {type(terms).__name__} "
                                f"{quote(terms)}")  # fmt: skip
    return [check_choice("terms", t, TERMS) for t in terms]


@dataclass(frozen=True)
class ShadeOptions:
    """What the illumination equation computes: its form, the distance in ``A(d)``, the terms, pruning.

    Parameters
    ----------
    form : {"classic", "physical"}
    attenuation_distance : {"light", "light+viewer"}
    terms : tuple of str
        Term names from :data:`TERMS`, in order.
    prune : bool
        Skip black lights and zero colours (``False``: the nothing-skipped loop that plans are
        measured against).
    """

    form: str = "classic"
    attenuation_distance: str = "light"
    terms: tuple = TERMS
    prune: bool = True

    @classmethod
    def checked(cls, form="classic", attenuation_distance="light", terms=TERMS, prune=True) -> ShadeOptions:
        """Options from unchecked arguments (``ValueError``/``ArgumentTypeError`` naming the bad one).

        Parameters
        ----------
        form, attenuation_distance, terms, prune
            As the class's fields; ``terms`` any sequence of term names.

        Returns
        -------
        ShadeOptions
        """
        form = check_choice("form", form, FORMS)
        attenuation_distance = check_choice("attenuation_distance", attenuation_distance, ("light", "light+viewer"))
        return cls(form, attenuation_distance, tuple(check_terms(terms)), prune)

    @property
    def scale(self) -> float:
        """1 for the classic form, ``1/π`` for the physical one (the engine's single π relation)."""
        return 1.0 if self.form == "classic" else 1.0 / math.pi


class Samples(NamedTuple):
    """Prepared inputs of the illumination equation, in one float dtype.

    ``points`` ``(N, 3)`` or ``None`` (only ambient and directional lights), ``unit_normals`` unit or
    zero, ``view`` unit view vectors (or one shared direction), ``eye_distance`` float64 distances to
    the eye (``None`` for a distant viewer), ``tangents`` the surface tangents that orient anisotropic
    models (``None``: each model's default frame; isotropic models never read them).
    """

    points: np.ndarray | None
    unit_normals: np.ndarray
    view: np.ndarray
    eye_distance: np.ndarray | None = None
    tangents: np.ndarray | None = None


def view_vectors(points, *, eye=None, view_dir=None, dtype=None):
    """The slides' ``v`` at ``points`` and the eye distances (None for a distant viewer).

    Exactly one of ``eye`` (a viewer position) or ``view_dir`` (the direction
    toward a viewer at infinity) must be given.  The eye distances are float64,
    saturated at its largest finite value.  The inputs are taken as checked
    (:func:`~lighting.shading.equation.shade` checks them); this is also the renderer's path.

    Parameters
    ----------
    points : numpy.ndarray, (..., 3)
        Surface positions (may be ``None`` with ``view_dir``).
    eye : 3-vector, optional
        The viewer's position.
    view_dir : 3-vector, optional
        The direction toward a distant viewer.
    dtype : numpy float dtype, optional
        Working dtype (default: that of ``points``).

    Returns
    -------
    tuple
        ``(v, eye distances)``: unit vectors in ``dtype`` and float64 distances, or
        ``(v, None)`` for a distant viewer.
    """
    dt = dtype or working_dtype(points)
    if (eye is None) == (view_dir is None):
        raise ValueError("give exactly one of eye (viewer position) or view_dir (direction toward a distant viewer)")
    if view_dir is not None:
        # Normalized in float64 first: a direction beyond float32's range (1e300, -1e300, 1e300) is
        # still a direction, and only its unit vector is cast.
        return normalize(as_float(view_dir, np.float64)).astype(dt), None
    e = as_float(eye, np.float64)
    if np.ndim(points) == 2 and np.shape(points)[1] == 3 and e.shape == (3,) and dt == np.float32:
        # A float32 renderer's view vectors, in float32 and one contiguous plane per component
        # (several times faster than float64 rows): the positions themselves carry float32
        # rounding, so this adds about one ulp to v's direction.
        p = as_float(points, dt)
        fi = np.finfo(dt)
        # Points far from the eye (1e30 in float32) overflow these squares: they take the float64 path below.
        with np.errstate(over="ignore", under="ignore", invalid="ignore"):
            d = [dt(e[k]) - p[:, k] for k in range(3)] if np.all(np.abs(e) < fi.max) else None
            len2 = None if d is None else d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
        if len2 is not None and np.all((len2 > fi.tiny * 1e4) & (len2 < fi.max * 1e-4)):
            dist = np.sqrt(len2)
            inv = 1 / dist
            v = np.empty(p.shape, dtype=dt, order="F")
            for k in range(3):
                np.multiply(d[k], inv, out=v[:, k])
            return v, dist.astype(np.float64)
    p = as_float(points, np.float64)
    with np.errstate(over="ignore", invalid="ignore"):
        d = e - p
    factor = 1.0
    if not np.all(np.isfinite(d)):
        # The difference of two finite positions overflowed (1e308 − (−1e308)): halves keep the direction.
        d, factor = 0.5 * e - 0.5 * p, 2.0
    with np.errstate(over="ignore"):
        dist = np.minimum(factor * length(d), np.finfo(np.float64).max)
    return normalize(d).astype(dt), dist


def prepare(points, normals, material, eye, view_dir, lights):
    """Check every argument once; points, unit normals, view vectors and eye distances in the working dtype.

    ``points`` may be ``None`` only when every light is ambient or directional (they do not depend on
    where the surface is) and the viewer is at infinity (``view_dir``).

    Parameters
    ----------
    points, normals, material, eye, view_dir, lights
        As :func:`lighting.shading.equation.shade`.

    Returns
    -------
    tuple
        ``(points or None, unit normals, view vectors, eye distances or None, list of lights)``.
    """
    check_material(material)
    lights = check_lights(lights)
    if (eye is None) == (view_dir is None):
        raise ValueError(
            "give exactly one of eye (viewer position) or view_dir (direction toward a distant viewer); "
            f"got eye={quote(eye)}, view_dir={quote(view_dir)}"
        )
    n = check_vectors("normals", normals)
    if points is None:
        positional = positional_lights(lights)
        if positional:
            raise points_needed_error(positional[0])
        if eye is not None:
            raise ArgumentTypeError("points must be finite real vectors of shape (..., 3) when eye= is given "
                                    "(v depends on the position); got None")  # fmt: skip
        p = None
        dt = working_dtype(n)
    else:
        p = check_vectors("points", points)
        dt = working_dtype(p, n)
    if eye is not None:
        e = check_vectors("eye", eye, dtype=np.float64)
        if e.shape != (3,):
            raise ValueError(f"eye must be one finite 3-vector (the viewer's position); got shape {e.shape}: "
                             f"{quote(eye)}")  # fmt: skip
    else:
        vd = check_vectors("view_dir", view_dir, nonzero=True)
        if vd.shape != (3,):
            raise ValueError(f"view_dir must be one finite nonzero 3-vector (the direction toward a viewer at "
                             f"infinity); got shape {vd.shape}: {quote(view_dir)}")  # fmt: skip
    shapes = {"points": None if p is None else p.shape, "normals": n.shape,
              "view_dir": None if view_dir is None else vd.shape}  # fmt: skip
    try:
        np.broadcast_shapes(*(s for s in shapes.values() if s is not None))
    except ValueError:
        given = ", ".join(f"{k} {s}" for k, s in shapes.items() if s is not None)
        raise ValueError(f"points, normals and view_dir must broadcast together (shapes (..., 3)); "
                         f"got {given}") from None
    p = None if p is None else as_float(p, dt)
    n = normalize(as_float(n, dt))
    v, eye_dist = view_vectors(p, eye=eye, view_dir=None if view_dir is None else vd, dtype=dt)
    return p, n, v, eye_dist, lights




def prepare_tangents(tangents, normals: np.ndarray):
    """Check the ``tangents=`` of :func:`~lighting.shading.equation.shade` against the prepared normals.

    Parameters
    ----------
    tangents : array_like, (..., 3), or None
        Surface tangents: finite, real, broadcasting with the normals (any length: a model makes its
        tangent unit and perpendicular to ``n``, and takes its default frame where it cannot).
    normals : numpy.ndarray, (..., 3)
        The prepared unit normals (their dtype is the working dtype).

    Returns
    -------
    numpy.ndarray or None
        The tangents in the normals' dtype, or ``None``.

    Raises
    ------
    ValueError
        Naming ``tangents``: NaN or infinite entries, a last axis other than 3, a shape that does not
        broadcast with the normals (``ArgumentTypeError`` for text, complex, booleans).
    """
    if tangents is None:
        return None
    t = check_vectors("tangents", tangents)
    try:
        np.broadcast_shapes(t.shape, normals.shape)
    except ValueError:
        raise ValueError(f"tangents must broadcast with the normals (shapes (..., 3)); got tangents {t.shape}, "
                         f"normals {normals.shape}") from None  # fmt: skip
    return as_float(t, normals.dtype.type)
