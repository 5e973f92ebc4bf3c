r"""The illumination equation, in the slides' classic form and in physical form.

Classic form (UBC deck, "Illumination Equation")::

    I = k_e + I_a k_a + Σ_p  I_p / A(d_p) · (k_d (n·l_p) + k_s (r_p·v)^n)

with every product taken per RGB channel ("red light on a green surface is
black").  The bracket is, for any model, its :meth:`~lighting.brdf.BRDF.classic`
term ``π f_r (n·l)``, so Blinn–Phong, normalized Blinn–Phong or Cook–Torrance
drop into the same sum.

Physical form (CMSC 435 deck, "Rendering Equation for Point Lights")::

    L_o(v) = Σ_i f_r(v, l_i) E_i (n·l_i)

where ``E_i = I_p / A(d_p)`` is the irradiance the light delivers on a surface
facing it.  The engine's single π relation (conventions.md) ties the two:
``I_classic = π L_o`` term by term, the ambient and emission terms included
(ambient light is a uniform irradiance ``I_a``, which a surface of albedo
``k_a`` turns into radiance ``k_a I_a / π``).  The two forms are computed by
two code paths (:meth:`classic` and :meth:`eval_cos`) and agree to rounding.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np

from ._numeric import as_float, check_choice, check_color, working_dtype
from .brdf import BRDF, Geometry
from .lights import AmbientLight, Light
from .vec import normalize

__all__ = ["Material", "shade", "shade_terms", "TERMS", "FORMS"]

TERMS = ("emission", "ambient", "diffuse", "specular")
FORMS = ("classic", "physical")


@dataclass(frozen=True)
class Material:
    """A surface: a reflectance model plus the slides' ambient and emission coefficients.

    Parameters
    ----------
    brdf : BRDF
        The reflectance model (``Lambert(kd) + Phong(ks, e)`` is the slides' surface).
    ambient : scalar or RGB, optional
        ``k_a``, the fraction of ambient light reflected.  Defaults to the
        model's diffuse albedo (``k_a = k_d``), which is the usual choice: ambient
        light then shows the object's own colour.
    emission : scalar or RGB
        ``k_e``, light the surface gives off itself (classic units).
    """

    brdf: BRDF
    ambient: object = None
    emission: object = 0.0

    def __post_init__(self):
        if not isinstance(self.brdf, BRDF):
            raise ValueError(f"brdf must be a lighting.brdf model (Lambert, Phong, ...); got {self.brdf!r}")
        ka = self.brdf.diffuse_albedo if self.ambient is None else self.ambient
        object.__setattr__(self, "ambient", check_color("ambient", ka))
        object.__setattr__(self, "emission", check_color("emission", self.emission))


class _Columns:
    """Accumulates ``Σ_k s_k c_k`` (scalar fields × RGB constants) one channel plane at a time.

    Working on contiguous 1-D planes and interleaving RGB once at the end is
    many times faster than multiplying ``(N, 3)`` arrays per term.
    """

    def __init__(self, shape, dt):
        self.shape, self.dt = shape, dt
        self.planes = [None, None, None]

    def add(self, field, light_scale, colour):
        if not np.any(colour):
            return
        with np.errstate(over="ignore"):
            f = field * light_scale if np.ndim(light_scale) or light_scale != 1 else field
            for ch in range(3):
                c = colour[ch]
                if c == 0:
                    continue
                term = f * self.dt(c)
                self.planes[ch] = term if self.planes[ch] is None else self.planes[ch] + term

    def total(self):
        big = np.finfo(self.dt).max
        out = np.zeros(self.shape + (3,), dtype=self.dt)
        for ch, plane in enumerate(self.planes):
            if plane is not None:
                out[..., ch] = np.minimum(plane, big)
        return out


def _view_vectors(points, eye, view_dir, dt):
    if (eye is None) == (view_dir is None):
        raise ValueError("give exactly one of eye (viewer position) or view_dir (direction toward a distant viewer)")
    if view_dir is not None:
        v = normalize(as_float(view_dir, dt))
        return v, None
    e = as_float(eye, np.float64)
    d = e - as_float(points, np.float64)
    dist = np.sqrt(np.sum(d * d, axis=-1))
    return normalize(d).astype(dt), dist


def shade_terms(
    points,
    normals,
    material: Material,
    lights: Sequence[Light | AmbientLight] | Iterable,
    *,
    eye=None,
    view_dir=None,
    form: str = "classic",
    attenuation_distance: str = "light",
    terms: Iterable[str] = TERMS,
) -> dict[str, np.ndarray]:
    """Each term of the illumination equation separately, as ``{name: (..., 3)}``.

    Parameters
    ----------
    points, normals : array_like, (..., 3)
        Surface positions and normals (normals need not be unit length; a zero
        normal receives only emission and ambient light).
    material : Material
    lights : sequence of lights
        :class:`~lighting.lights.AmbientLight` adds to the ambient term, every
        other light to the diffuse and specular terms.
    eye, view_dir : 3-vector
        Exactly one: the viewer's position (perspective, ``v`` varies per point)
        or the direction toward a viewer at infinity.
    form : {"classic", "physical"}
        ``classic`` is the slides' ``I``; ``physical`` is radiance ``I / π``.
    attenuation_distance : {"light", "light+viewer"}
        ``d_p`` in ``A(d_p)``: the light's distance (usual), or the UBC slide's
        literal "distance to the light plus distance to the viewer".
    terms : iterable of {"emission", "ambient", "diffuse", "specular"}
        Which terms to compute; the others are not evaluated at all.

    Returns
    -------
    dict
        One ``(..., 3)`` array per requested term, in the working dtype.
    """
    form = check_choice("form", form, FORMS)
    attenuation_distance = check_choice("attenuation_distance", attenuation_distance, ("light", "light+viewer"))
    wanted = [check_choice("terms", t, TERMS) for t in terms]
    dt = working_dtype(points, normals)
    p = as_float(points, dt)
    n = normalize(as_float(normals, dt))
    shape = np.broadcast_shapes(p.shape, n.shape)
    scale = 1.0 if form == "classic" else 1.0 / math.pi
    lights = list(lights)
    out: dict[str, np.ndarray] = {}

    def const(rgb):
        return np.broadcast_to((rgb * scale).astype(dt), shape).copy()

    if "emission" in wanted:
        out["emission"] = const(material.emission)
    if "ambient" in wanted:
        total = sum((lt.radiant for lt in lights if isinstance(lt, AmbientLight)), np.zeros(3))
        out["ambient"] = const(total * material.ambient)

    want_parts = [t for t in ("diffuse", "specular") if t in wanted]
    if want_parts:
        parts = {t: [m for m in material.brdf.parts if m.term == t] for t in want_parts}
        v, eye_dist = _view_vectors(p, eye, view_dir, dt)
        if attenuation_distance == "light+viewer" and eye_dist is None:
            raise ValueError("attenuation_distance='light+viewer' needs eye= (a viewer position)")
        extra = eye_dist if attenuation_distance == "light+viewer" else None
        # Each (model term × light incidence) is a scalar field times an RGB constant;
        # gather the fields as columns and apply the colours with one matrix product.
        columns = {t: _Columns(shape[:-1], dt) for t in want_parts}
        for light in lights:
            if isinstance(light, AmbientLight) or light.is_black:
                continue
            for inc in light.incident(p, dtype=dt, extra_distance=extra):
                g = Geometry(n, inc.direction, v, unit=True, dtype=dt)
                for t in want_parts:
                    for model in parts[t]:
                        terms = model.separable_classic(g) if form == "classic" else model.separable_cos(g)
                        for field, colour in terms:
                            columns[t].add(field, inc.scale, colour * inc.radiant.astype(np.float64))
        for t in want_parts:
            out[t] = columns[t].total()
    return out


def shade(points, normals, material, lights, *, eye=None, view_dir=None, form="classic", **kwargs) -> np.ndarray:
    """Colour of surface points under lights: the slides' illumination equation.

    Sums :func:`shade_terms` (see there for the parameters).

    Examples
    --------
    Red light on a green surface is black:

    >>> from lighting.brdf import Lambert
    >>> from lighting.lights import DirectionalLight
    >>> shade((0, 0, 0.0), (0, 0, 1.0), Material(Lambert((0, 1, 0))),
    ...       [DirectionalLight((0, 0, 1.0), color=(1, 0, 0))], view_dir=(0, 0, 1.0)).tolist()
    [0.0, 0.0, 0.0]
    """
    parts = shade_terms(points, normals, material, lights, eye=eye, view_dir=view_dir, form=form, **kwargs)
    total = sum(parts.values())
    with np.errstate(over="ignore"):
        return np.minimum(total, np.finfo(total.dtype).max)
