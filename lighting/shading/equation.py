r"""The illumination equation, in the slides' classic form and in physical form.

Classic form (UBC deck, "Illumination Equation"):

    I = k_e + I_a k_a + Σ_p  I_p / A(d_p) · (k_d (n·l_p) + k_s (r_p·v)^n)

with every product taken per RGB channel ("red light on a green surface is
black").  The bracket is, for any model, its :meth:`~lighting.models.brdf.BRDF.classic`
term ``π f_r (n·l)``, so Blinn–Phong, normalized Blinn–Phong or Cook–Torrance
drop into the same sum.

Physical form (CMSC 435 deck, "Rendering Equation for Point Lights"):

    L_o(v) = Σ_i f_r(v, l_i) E_i (n·l_i)

where ``E_i = I_p / A(d_p)`` is the irradiance the light delivers on a surface
facing it.  The engine's single π relation (conventions.md) ties the two:
``I_classic = π L_o`` term by term, the ambient and emission terms included
(ambient light is a uniform irradiance ``I_a``, which a surface of albedo
``k_a`` turns into radiance ``k_a I_a / π``).  The two forms are computed by
two code paths (:meth:`classic` and :meth:`eval_cos`) and agree to rounding.

Where things live: :mod:`~lighting.shading.reference` is this equation as a
plain loop over lights (the docs' and the tests' oracle);
:mod:`~lighting.shading.batch` is the fast path that :func:`shade` runs (channel
sums, stacked directional lights, threads); :mod:`~lighting.shading.inputs`
checks the arguments and computes ``v``; :mod:`~lighting.shading.material`
holds :class:`Material`.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np

from .batch import shade_prepared, shade_prepared_terms
from .inputs import FORMS, TERMS, prepare, prepare_tangents, view_vectors
from .material import Material

__all__ = ["Material", "shade", "shade_terms", "shade_prepared", "view_vectors", "TERMS", "FORMS"]


def shade_terms(
    points,
    normals,
    material: Material,
    lights: Sequence | Iterable,
    *,
    eye=None,
    view_dir=None,
    form: str = "classic",
    attenuation_distance: str = "light",
    terms: Iterable[str] = TERMS,
    tangents=None,
) -> dict[str, np.ndarray]:
    """Each term of the illumination equation separately, as ``{name: (..., 3)}``.

    Parameters
    ----------
    points, normals : array_like, (..., 3)
        Surface positions and normals (normals need not be unit length; a zero
        normal receives only emission and ambient light).
    material : Material
    lights : sequence of lights
        :class:`~lighting.lights.punctual.AmbientLight` adds to the ambient term, every
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
    tangents : array_like, (..., 3), optional
        Surface tangents (broadcasting with ``normals``) that orient anisotropic models (Ward,
        anisotropic Cook–Torrance, Ashikhmin–Shirley, Disney): each is made unit and perpendicular to
        its normal by the model.  ``None``: each model's default frame
        (:attr:`lighting.models.geometry.Geometry.t`).  Isotropic models ignore them.

    Returns
    -------
    dict
        One ``(..., 3)`` array per requested term, in the working dtype.
    """
    p, n, v, eye_dist, lights = prepare(points, normals, material, eye, view_dir, lights)
    return shade_prepared_terms(p, n, v, material, lights, eye_distance=eye_dist, form=form,
                                attenuation_distance=attenuation_distance, terms=terms,
                                tangents=prepare_tangents(tangents, n))  # fmt: skip


def shade(
    points,
    normals,
    material,
    lights,
    *,
    eye=None,
    view_dir=None,
    form="classic",
    attenuation_distance="light",
    terms=TERMS,
    tangents=None,
) -> np.ndarray:
    """Colour of surface points under lights: the slides' illumination equation.

    The sum of the :func:`shade_terms`, accumulated directly.

    Parameters
    ----------
    points, normals, material, lights, eye, view_dir, form, attenuation_distance, terms, tangents
        As :func:`shade_terms`.

    Returns
    -------
    numpy.ndarray
        Colours ``(..., 3)`` in the working dtype (float32 in, float32 out).

    Examples
    --------
    Red light on a green surface is black:

    >>> from lighting.models.brdf import Lambert
    >>> from lighting.lights.punctual import DirectionalLight
    >>> shade((0, 0, 0.0), (0, 0, 1.0), Material(Lambert((0, 1, 0))),
    ...       [DirectionalLight((0, 0, 1.0), color=(1, 0, 0))], view_dir=(0, 0, 1.0)).tolist()
    [0.0, 0.0, 0.0]
    """
    p, n, v, eye_dist, lights = prepare(points, normals, material, eye, view_dir, lights)
    return shade_prepared(p, n, v, material, lights, eye_distance=eye_dist, form=form,
                          attenuation_distance=attenuation_distance, terms=terms,
                          tangents=prepare_tangents(tangents, n))  # fmt: skip
