r"""The OpenGL 1.x / 2.1 fixed-function lighting equation, per vertex.

This module evaluates the colour that the fixed-function pipeline of OpenGL
computes for a lit vertex, exactly as the OpenGL 2.1 specification §2.14.1
states it (single colour, one-sided, front material).  Everything is in *eye
coordinates*: the eye sits at the origin and looks down ``-z``; positions,
normals, light positions and spot directions are taken to be already
transformed by the modelview matrix (OpenGL transforms a light's position and
spot direction by the modelview matrix current when ``glLight`` is called).

A second statement of the equation, on purpose
-----------------------------------------------
This module does not call :mod:`lighting.lights` (``falloff``,
``SpotLight.spot_factor``) nor :mod:`lighting.shading.equation`: it keeps its
own transcription of the specification's formulas (the attenuation
``1 / (k_0 + k_1 d + k_2 d²)`` in the specification's coefficient order, the
spot factor, the half vector), tested against Mesa.  It is an independent
second statement of the lighting equation, so a drift in the engine's one
home of a formula shows up as a disagreement instead of being copied here.

The equation
------------
For a vertex ``V`` with unit normal ``n`` the primary colour is

$$
c = e_{cm} + a_{cm} a_{cs}
    + \sum_i att_i \, spot_i \,
      \bigl[ a_{cm} a_{cli} + (n \odot \hat{VP}_{pli}) d_{cm} d_{cli}
             + f_i (n \odot \hat{h}_i)^{s_{rm}} s_{cm} s_{cli} \bigr]
$$

with, per colour channel (products of colours are componentwise):

- ``u ⊙ v = max(u · v, 0)``;
- ``VP_i``: the unit vector from the vertex to light ``i``.  For a light at
  ``(x, y, z, w)`` with ``w = 0`` it is ``normalize(x, y, z)`` (a directional
  light: ``xyz`` points *toward* the light); otherwise it is
  ``normalize(xyz / w - V)``;
- ``f_i = 1`` if ``n ⊙ VP_i ≠ 0`` and ``0`` otherwise: no highlight from a
  light behind the surface, whatever the shininess;
- ``h_i = normalize(VP_i + VP_e)`` with a *local viewer* (``VP_e`` the unit
  vector from the vertex to the eye at the origin), otherwise
  ``h_i = normalize(VP_i + (0, 0, 1))`` (the *infinite viewer* looks along
  ``-z`` from infinitely far away);
- ``att_i = 1 / (k_0 + k_1 d + k_2 d²)`` with ``d`` the vertex-light
  distance, for positional lights; ``att_i = 1`` for directional ones;
- ``spot_i = max(-VP_i · ŝ_i, 0)^{s_{rli}}`` when the spot cutoff
  ``c_{rli}`` is not 180° and the *raw* cosine ``-VP_i · ŝ_i`` is at least
  ``cos(c_{rli})``; ``0`` when it is smaller; ``1`` when ``c_{rli} = 180°``.
  ``P_{pli}V = -VP_i`` is the direction from the light to the vertex and
  ``ŝ_i`` the normalized spot direction.  The specification applies the spot
  factor to every light, directional ones included (see "The spot cone test"
  below for why the raw cosine);
- the specification defines ``0^0 = 1`` (so a shininess of 0 gives a
  highlight of exactly ``s_cm s_cli`` wherever ``f_i = 1``, and a spot
  exponent of 0 gives ``spot_i = 1`` everywhere inside the cone).

The result is clamped to ``[0, 1]``; its alpha is the material's diffuse
alpha.  The per-light ambient term is attenuated and spot-masked like the
rest: a spot light's ambient contribution stops at the edge of its cone.

The spot cone test: the implementations' reading
------------------------------------------------
The OpenGL 2.1 specification (§2.14.1, the definition of ``spot_i``) reads

    spot_i = (P_pli V ⊙ ŝ_dli)^{s_rli},  c_rli ≠ 180.0,  P_pli V ⊙ ŝ_dli ≥ cos(c_rli),
             0.0,                      c_rli ≠ 180.0,  P_pli V ⊙ ŝ_dli < cos(c_rli),
             1.0,                      c_rli = 180.0,

with ``⊙`` the *clamped* dot product.  Taken to the letter this is degenerate
for the largest finite cutoff, 90°: the clamped cosine is never below
``cos 90° = 0``, so a 90° "cone" lights the whole sphere around the light,
behind its plane included (with ``0^0 = 1`` there for a spot exponent of 0).
Implementations test the *raw* cosine instead, and a 90° cutoff lights the
half-space in front of the spot's plane: Mesa's fixed-function vertex
program compares ``-VP·ŝ`` with ``max(cos(c_rli), 0)`` before taking the
absolute value for the power, and its classic T&L path skips a light when
``-VP·ŝ < cos(c_rli)``.  This module follows the implementations (as
conventions.md asks): a vertex is inside when ``-VP·ŝ >= cos(c_rli)``, and
the spot factor is ``max(-VP·ŝ, 0)^{s_rli}`` there.  For every cutoff below
90° the two readings agree (the raw cosine is positive wherever it passes).
Exactly on the spot's plane at 90° (``-VP·ŝ = 0``) this module, like the
specification and Mesa's classic path, counts the vertex as inside; Mesa's
vertex-program path uses a strict ``>`` there.  ``cos(c_rli)`` is exact at
0° and 90° (:func:`lighting.numerics.cos_sin_deg`), so ``cos 90°`` is 0,
not 6.1e-17.

Degenerate cases (the specification leaves them undefined)
----------------------------------------------------------
This module keeps "finite in, finite out" and defines them as follows:

- a vertex exactly at a positional light: ``d = 0`` and ``VP_i`` is the zero
  vector, so there is no diffuse or specular term (``f_i = 0``) and the
  light-to-vertex cosine used by the spot test is 0 (inside a 90° cone only);
- an attenuation denominator of 0 (``k_0 = 0`` at ``d = 0``) saturates
  ``att_i`` at the largest finite double; the colour is then clamped;
- a zero half vector (``VP_i + VP_e = 0``) stays the zero vector, so
  ``(n ⊙ h_i)^s = 0^s``, which is 1 when ``s = 0``;
- a zero normal gives no diffuse or specular term;
- a vertex at the eye with a local viewer has ``VP_e = 0``.

Accuracy: the arithmetic is done in float64 whatever the input dtype, well
within the "about one part in 10^5" the specification asks for; the result is
cast to the dtype of the inputs at the end.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from .._budget import check_budget
from .._text import quote
from .._validate import ArgumentTypeError, check_bool, check_count, check_vectors, real_array
from ..numerics import cos_sin_deg, working_dtype
from ..vec import _dot

__all__ = ["Material", "Light", "shade_vertices", "GL_MAX_SHININESS", "GL_MAX_SPOT_EXPONENT"]

#: Largest shininess and spot exponent the specification accepts.
GL_MAX_SHININESS = 128.0
GL_MAX_SPOT_EXPONENT = 128.0

_BIG = float(np.finfo(np.float64).max)


# --------------------------------------------------------------------------- validation
def _rgba(name: str, value) -> tuple[float, float, float, float]:
    """An RGBA colour from an RGB triple (alpha 1) or an RGBA 4-tuple.

    Any finite value is accepted: the specification gives colour components
    the range (-inf, +inf) (a negative light colour darkens).
    """
    allowed = "an RGB triple or RGBA 4-tuple of finite numbers"
    arr = real_array(name, value, allowed=allowed, dtype=np.float64)
    if arr.shape not in ((3,), (4,)):
        raise ValueError(f"{name} must be {allowed}; got {quote(value)}")
    if arr.shape == (3,):
        arr = np.append(arr, 1.0)
    return tuple(float(c) for c in arr)


def _real(name: str, value, allowed: str) -> float:
    """A finite real scalar (a Python or NumPy number, or a 0-d real array); bools, text and complex are types."""
    if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "fiu":
        value = value.item()
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (numbers.Real, np.integer, np.floating)):
        raise ArgumentTypeError(f"{name} must be {allowed}; got {type(value).__name__} {quote(value)}")
    try:
        v = float(value)
    except OverflowError:  # a Python int beyond the float range
        raise ValueError(f"{name} must be {allowed}; got {quote(value)}") from None
    if not math.isfinite(v):
        raise ValueError(f"{name} must be {allowed}; got {v!r}")
    return v


def _in_range(name: str, value, lo: float, hi: float) -> float:
    allowed = f"a finite number in [{lo:g}, {hi:g}]"
    v = _real(name, value, allowed)
    if not lo <= v <= hi:
        raise ValueError(f"{name} must be {allowed}; got {v!r}")
    return v


# --------------------------------------------------------------------------- parameters
@dataclass(frozen=True)
class Material:
    """Front material of the fixed-function pipeline (``glMaterial``).

    Parameters
    ----------
    ambient, diffuse, specular, emission : sequence of float
        ``a_cm``, ``d_cm``, ``s_cm``, ``e_cm``: RGBA 4-tuples, or RGB triples
        (alpha 1).  Stored as 4-tuples of floats.  Only the diffuse alpha
        reaches the result (it is the vertex alpha).
    shininess : float
        Specular exponent ``s_rm``, in ``[0, 128]`` as in OpenGL.

    Notes
    -----
    Defaults are OpenGL's initial material state.

    Example
    -------
    >>> Material(diffuse=(0.0, 1.0, 0.0)).diffuse
    (0.0, 1.0, 0.0, 1.0)
    """

    ambient: tuple = (0.2, 0.2, 0.2, 1.0)
    diffuse: tuple = (0.8, 0.8, 0.8, 1.0)
    specular: tuple = (0.0, 0.0, 0.0, 1.0)
    emission: tuple = (0.0, 0.0, 0.0, 1.0)
    shininess: float = 0.0

    def __post_init__(self):
        for name in ("ambient", "diffuse", "specular", "emission"):
            object.__setattr__(self, name, _rgba(name, getattr(self, name)))
        # The specification allows any value, but a negative *reflectance* is an error by
        # the engine's contract (conventions.md); emission and light colours stay free.
        for name in ("ambient", "diffuse", "specular"):
            rgba = getattr(self, name)
            if any(c < 0 for c in rgba):
                raise ValueError(f"{name} (a reflectance) must have every component >= 0; got {rgba!r}")
        object.__setattr__(self, "shininess", _in_range("shininess", self.shininess, 0.0, GL_MAX_SHININESS))


@dataclass(frozen=True)
class Light:
    """One light source of the fixed-function pipeline (``glLight``), in eye space.

    Parameters
    ----------
    ambient, diffuse, specular : sequence of float
        ``a_cli``, ``d_cli``, ``s_cli``: RGBA 4-tuples or RGB triples.
    position : sequence of float
        ``(x, y, z, w)``.  ``w = 0``: a directional light, ``(x, y, z)`` the
        direction *toward* it (must be nonzero).  Otherwise a positional light
        at ``(x, y, z) / w``.  A 3-sequence means ``w = 1``.
    spot_direction : sequence of float
        ``s_dli``, the axis of the spot cone (nonzero; normalized when used).
    spot_exponent : float
        ``s_rli`` in ``[0, 128]``.
    spot_cutoff : float
        ``c_rli``, the half-angle of the cone in degrees: in ``[0, 90]`` or
        exactly 180 (no spot).
    constant_attenuation, linear_attenuation, quadratic_attenuation : float
        ``k_0, k_1, k_2 >= 0``, not all zero.  Used only when ``w != 0``.

    Notes
    -----
    Defaults are those of ``GL_LIGHT0``; :meth:`gl_default` gives the other
    lights' (black diffuse and specular).

    Example
    -------
    >>> Light(position=(0, 0, 0, 1), quadratic_attenuation=1.0).is_directional
    False
    """

    ambient: tuple = (0.0, 0.0, 0.0, 1.0)
    diffuse: tuple = (1.0, 1.0, 1.0, 1.0)
    specular: tuple = (1.0, 1.0, 1.0, 1.0)
    position: tuple = (0.0, 0.0, 1.0, 0.0)
    spot_direction: tuple = (0.0, 0.0, -1.0)
    spot_exponent: float = 0.0
    spot_cutoff: float = 180.0
    constant_attenuation: float = 1.0
    linear_attenuation: float = 0.0
    quadratic_attenuation: float = 0.0

    def __post_init__(self):
        for name in ("ambient", "diffuse", "specular"):
            object.__setattr__(self, name, _rgba(name, getattr(self, name)))

        allowed = "(x, y, z, w) (or (x, y, z), w = 1) of finite numbers"
        pos = real_array("position", self.position, allowed=allowed, dtype=np.float64)
        if pos.shape == (3,):
            pos = np.append(pos, 1.0)
        if pos.shape != (4,):
            raise ValueError(f"position must be {allowed}; got {quote(self.position)}")
        if pos[3] == 0.0 and not np.any(pos[:3]):
            raise ValueError(
                "position must give a nonzero direction (x, y, z) when w = 0 "
                f"(a directional light); got {quote(self.position)}"
            )
        object.__setattr__(self, "position", tuple(float(c) for c in pos))

        allowed = "a nonzero (x, y, z) of finite numbers"
        sd = real_array("spot_direction", self.spot_direction, allowed=allowed, dtype=np.float64)
        if sd.shape != (3,) or not np.any(sd):
            raise ValueError(f"spot_direction must be {allowed}; got {quote(self.spot_direction)}")
        object.__setattr__(self, "spot_direction", tuple(float(c) for c in sd))

        object.__setattr__(
            self,
            "spot_exponent",
            _in_range("spot_exponent", self.spot_exponent, 0.0, GL_MAX_SPOT_EXPONENT),
        )
        allowed = "a number of degrees in [0, 90], or exactly 180 (no spot)"
        cutoff = _real("spot_cutoff", self.spot_cutoff, allowed)
        if not (0.0 <= cutoff <= 90.0 or cutoff == 180.0):
            raise ValueError(f"spot_cutoff must be {allowed}; got {cutoff!r}")
        object.__setattr__(self, "spot_cutoff", cutoff)

        ks = []
        for name in ("constant_attenuation", "linear_attenuation", "quadratic_attenuation"):
            k = _real(name, getattr(self, name), "a finite number >= 0")
            if not k >= 0.0:
                raise ValueError(f"{name} must be a finite number >= 0; got {k!r}")
            object.__setattr__(self, name, k)
            ks.append(k)
        if not any(ks):
            raise ValueError(
                "constant_attenuation, linear_attenuation and quadratic_attenuation "
                "must not all be zero (the attenuation 1 / (k0 + k1 d + k2 d^2) "
                "would be infinite); got (0.0, 0.0, 0.0)"
            )

    @classmethod
    def gl_default(cls, index: int = 0, **overrides) -> Light:
        """OpenGL's initial state of ``GL_LIGHT<index>``, with ``overrides`` applied.

        ``GL_LIGHT0`` has white diffuse and specular colours; every other
        light starts with black ones (so enabling it alone changes nothing).

        Parameters
        ----------
        index : int >= 0, default 0
            The ``i`` of ``GL_LIGHTi``.
        **overrides
            Fields of :class:`Light` to set instead of their defaults.

        Returns
        -------
        Light

        Example
        -------
        >>> Light.gl_default(1).diffuse
        (0.0, 0.0, 0.0, 1.0)
        """
        index = check_count("index", index, 0)
        if index > 0:
            overrides.setdefault("diffuse", (0.0, 0.0, 0.0, 1.0))
            overrides.setdefault("specular", (0.0, 0.0, 0.0, 1.0))
        return cls(**overrides)

    @property
    def is_directional(self) -> bool:
        """True for ``w = 0`` (a light infinitely far away, no attenuation)."""
        return self.position[3] == 0.0

    @property
    def is_spot(self) -> bool:
        """True when the spot cutoff is not 180°."""
        return self.spot_cutoff != 180.0


# --------------------------------------------------------------------------- numerics
def _unit(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(v / |v|, |v|)`` over the last axis; the zero vector stays zero.

    Scaling by the largest component first keeps ``|v|²`` from overflowing or
    underflowing for any finite ``v``.
    """
    m = np.max(np.abs(v), axis=-1, keepdims=True)
    nonzero = m > 0
    u = v / np.where(nonzero, m, 1.0)
    norm = np.sqrt(np.sum(u * u, axis=-1, keepdims=True))  # in [1, √3] where nonzero
    unit = u / np.where(nonzero, norm, 1.0)
    length = np.minimum(m * norm, _BIG)  # only |v| near the float64 limit can overflow
    return unit, length[..., 0]


def _sat(x: np.ndarray) -> np.ndarray:
    """Clamp to the finite float64 range (an overflowed ``±inf`` becomes ``±max``)."""
    return np.clip(x, -_BIG, _BIG)


def _light_list(lights) -> list[Light]:
    if isinstance(lights, Light):
        return [lights]
    if isinstance(lights, (str, bytes, bytearray, dict)):
        raise ArgumentTypeError(
            f"lights must be a Light or a sequence of Light; got {type(lights).__name__} {quote(lights)}"
        )
    try:
        out = list(lights)
    except TypeError:
        raise ArgumentTypeError(
            f"lights must be a Light or a sequence of Light; got {type(lights).__name__} {quote(lights)}"
        ) from None
    for i, light in enumerate(out):
        if not isinstance(light, Light):
            raise ArgumentTypeError(f"lights[{i}] must be a Light; got {type(light).__name__} {quote(light)}")
    return out


#: Peak bytes per vertex of :func:`shade_vertices` (float64 temporaries of one light), for the memory budget.
_BYTES_PER_VERTEX = 48 * 8


# --------------------------------------------------------------------------- shading
def shade_vertices(
    positions,
    normals,
    material: Material,
    lights: Light | Iterable[Light],
    scene_ambient=(0.2, 0.2, 0.2, 1.0),
    local_viewer: bool = False,
    *,
    normalize: bool = True,
) -> np.ndarray:
    r"""Lit vertex colours of the OpenGL fixed-function pipeline (OpenGL 2.1 specification §2.14.1).

    $$
    c = e_{cm} + a_{cm} a_{cs} + \sum_i att_i\, spot_i\,
        [a_{cm} a_{cli} + (n \odot VP_i) d_{cm} d_{cli}
         + f_i (n \odot \hat h_i)^{s_{rm}} s_{cm} s_{cli}]
    $$

    clamped to ``[0, 1]``; see the module docstring for every term and for the
    degenerate cases.

    Parameters
    ----------
    positions : array_like, shape (..., 3)
        Vertex positions in eye coordinates (eye at the origin, looking down
        ``-z``).
    normals : array_like, shape (..., 3)
        Vertex normals in eye coordinates; broadcast against ``positions``.
        The equation assumes unit normals.
    material : Material
        The front material.
    lights : Light or sequence of Light
        The enabled lights, in eye coordinates (OpenGL guarantees at least 8;
        any number is accepted here).  An empty sequence leaves only
        ``e_cm + a_cm a_cs``.
    scene_ambient : sequence of float, optional
        ``a_cs``, the light model's ambient colour (RGB or RGBA; alpha unused).
    local_viewer : bool, optional
        ``GL_LIGHT_MODEL_LOCAL_VIEWER``: the half vector uses the direction
        to the eye at the origin instead of ``(0, 0, 1)``.
    normalize : bool, optional, keyword-only
        Normalize the normals first, like ``glEnable(GL_NORMALIZE)`` (the
        default here, unlike OpenGL's).  With ``False`` the normals are used
        as given, as OpenGL does without ``GL_NORMALIZE``: a non-unit normal
        scales the diffuse and specular cosines.  A zero normal is finite
        either way (no diffuse or specular term).

    Returns
    -------
    ndarray, shape (..., 4)
        RGBA in ``[0, 1]``; alpha is the material's diffuse alpha (clamped).
        float32 when the array inputs are float32, else float64; the
        arithmetic is float64 throughout.

    Raises
    ------
    ValueError
        Naming the argument: non-finite or wrongly shaped positions/normals,
        shapes that do not broadcast, more vertices than the memory budget
        allows (:func:`lighting._budget.memory_budget`), a bad
        ``scene_ambient``.  Wrong types (text, complex, booleans as numbers,
        ``None``, a non-Material ``material``, a non-Light entry in
        ``lights``, a non-bool flag) raise ``ArgumentTypeError``, which is both
        a ``TypeError`` and a ``ValueError``.  A zero normal is legal (see
        ``normalize``); positions may be anywhere, the eye and the lights
        included.

    Example
    -------
    A red light shining straight onto a green surface reflects nothing:

    >>> red = Light(diffuse=(1, 0, 0), specular=(0, 0, 0))
    >>> green = Material(ambient=(0, 0, 0), diffuse=(0, 1, 0))
    >>> shade_vertices((0, 0, -1), (0, 0, 1), green, [red], scene_ambient=(0, 0, 0)).tolist()
    [0.0, 0.0, 0.0, 1.0]
    """
    if not isinstance(material, Material):
        raise ArgumentTypeError(f"material must be a Material; got {type(material).__name__} {quote(material)}")
    lights = _light_list(lights)
    a_cs = np.array(_rgba("scene_ambient", scene_ambient)[:3])
    local_viewer = check_bool("local_viewer", local_viewer)
    normalize = check_bool("normalize", normalize)

    out_dtype = working_dtype(positions, normals)
    p = check_vectors("positions", positions, dtype=np.float64)
    n = check_vectors("normals", normals, dtype=np.float64)
    try:
        shape = np.broadcast_shapes(p.shape, n.shape)
    except ValueError:
        raise ValueError(f"positions and normals must broadcast together; got shapes {p.shape} and {n.shape}") from None
    vertices = math.prod(shape[:-1])
    check_budget("positions, normals", vertices * _BYTES_PER_VERTEX, what=f"{vertices} vertices")
    p = np.broadcast_to(p, shape)
    n = np.broadcast_to(n, shape)

    a_cm = np.array(material.ambient[:3])
    d_cm = np.array(material.diffuse[:3])
    s_cm = np.array(material.specular[:3])
    e_cm = np.array(material.emission[:3])
    s_rm = material.shininess

    # Overflow can only come from extreme (but finite) colours, positions or a
    # vanishing attenuation denominator; every such value is saturated to the
    # finite range right away and clamped to [0, 1] at the end.  Underflow
    # (a tiny cosine raised to the power 128) is exactly the 0 we want.
    with np.errstate(over="ignore", under="ignore"):
        if normalize:
            n, _ = _unit(n)
        if local_viewer:
            vp_e, _ = _unit(-p)
        else:
            vp_e = np.array([0.0, 0.0, 1.0])

        color = np.broadcast_to(_sat(e_cm + _sat(a_cm * a_cs)), shape).copy()

        for light in lights:
            # Per-light colour products (OpenGL implementations precompute
            # these too), saturated so their sum cannot become inf - inf.
            amb = _sat(a_cm * np.array(light.ambient[:3]))
            dif = _sat(d_cm * np.array(light.diffuse[:3]))
            spe = _sat(s_cm * np.array(light.specular[:3]))

            x, y, z, w = light.position
            if w == 0.0:
                vp, _ = _unit(np.array([x, y, z]))
                vp = np.broadcast_to(vp, shape)
                att = np.ones(shape[:-1])
            else:
                p_light = _sat(np.array([x, y, z]) / w)
                vp, d = _unit(_sat(p_light - p))
                k0, k1, k2 = (
                    light.constant_attenuation,
                    light.linear_attenuation,
                    light.quadratic_attenuation,
                )
                # A zero coefficient must drop its term even where d² overflowed
                # (0 · inf would be NaN).
                den = k0 + (k1 * d if k1 else 0.0) + (k2 * (d * d) if k2 else 0.0)
                # den == 0 only at d == 0 with k0 == 0: the attenuation is
                # infinite there, so saturate it rather than divide by zero.
                att = np.where(den > 0, 1.0 / np.where(den > 0, den, 1.0), _BIG)
                att = _sat(att)

            if light.is_spot:
                s_hat, _ = _unit(np.array(light.spot_direction))
                cos_s = -_dot(vp, s_hat)
                # The raw cosine decides (see the module docstring), so a 90° cone is a half-space.
                inside = cos_s >= float(cos_sin_deg(light.spot_cutoff)[0])
                spot = np.where(inside, np.power(np.maximum(cos_s, 0.0), light.spot_exponent), 0.0)
                att = att * spot

            # Only un-normalized normals can push these past the float range;
            # kept finite so that a zero colour times them is 0, not NaN.
            n_dot_vp = _sat(np.maximum(_dot(n, vp), 0.0))
            f = n_dot_vp > 0.0
            h, _ = _unit(vp + vp_e)
            n_dot_h = np.maximum(_dot(n, h), 0.0)
            spec = _sat(np.where(f, np.power(n_dot_h, s_rm), 0.0))

            bracket = _sat(amb + _sat(n_dot_vp[..., None] * dif) + _sat(spec[..., None] * spe))
            color = _sat(color + _sat(att[..., None] * bracket))

    rgba = np.empty(shape[:-1] + (4,), dtype=np.float64)
    rgba[..., :3] = np.clip(color, 0.0, 1.0)
    rgba[..., 3] = min(max(material.diffuse[3], 0.0), 1.0)
    return rgba.astype(out_dtype, copy=False)
