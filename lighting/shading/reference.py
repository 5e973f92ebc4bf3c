r"""The slides' illumination equation as a plain loop over lights: the reference.

Classic form (UBC deck, "Illumination Equation"):

    I = k_e + I_a k_a + Σ_p  I_p / A(d_p) · (k_d (n·l_p) + k_s (r_p·v)^e)

Physical form (CMSC 435 deck, "Rendering Equation for Point Lights"):

    L_o(v) = (k_e + I_a k_a) / π + Σ_p f_r(v, l_p) (n·l_p) · I_p / A(d_p)

For any model the bracket ``k_d (n·l) + k_s (r·v)^e`` is its public
``classic(n, l, v)`` (``π f_r (n·l)``) and ``f_r (n·l)`` is its ``eval_cos``;
``I_p / A(d_p)`` is what each light's public :meth:`~lighting.lights.punctual.Light.incident`
yields (one record for a point light, one per sample for an area light).

:func:`shade_reference` is that sum written out, in float64, with nothing
skipped and nothing stacked.  It is slow and meant to be read: the docs show
it, and the tests hold :func:`~lighting.shading.equation.shade` and the
renderer (:mod:`lighting.shading.batch`, the fast path) to it on random scenes.
"""

from __future__ import annotations

import numpy as np

from ..lights.punctual import AmbientLight
from .inputs import ShadeOptions, prepare, prepare_tangents

__all__ = ["shade_reference"]


def shade_reference(points, normals, material, lights, *, eye=None, view_dir=None, form="classic",
                    attenuation_distance="light", tangents=None) -> np.ndarray:  # fmt: skip
    """The illumination equation as a loop over lights, in float64 (the oracle of the tests).

    Parameters
    ----------
    points, normals : array_like, (N, 3)
        Surface positions and normals (normalized here; ``points`` may be ``None`` when every
        light is ambient or directional and the viewer is at infinity).
    material : Material
    lights : sequence of lights
    eye, view_dir : 3-vector
        Exactly one: the viewer's position, or the direction toward a viewer at infinity.
    form : {"classic", "physical"}
    attenuation_distance : {"light", "light+viewer"}
        As :func:`~lighting.shading.equation.shade`.
    tangents : array_like, (N, 3), optional
        Surface tangents for anisotropic models (``tangent=`` of their ``classic``/``eval_cos``);
        ``None``: each model's default frame.

    Returns
    -------
    numpy.ndarray
        Colours ``(N, 3)`` in float64, whatever the input dtype.

    Examples
    --------
    >>> from lighting import DirectionalLight, Lambert, Material
    >>> shade_reference([(0, 0, 0.0)], [(0, 0, 1.0)], Material(Lambert(0.5)), [DirectionalLight((0, 0, 1.0))],
    ...                 view_dir=(0, 0, 1.0)).tolist()
    [[0.5, 0.5, 0.5]]
    """
    options = ShadeOptions.checked(form, attenuation_distance)
    p, n, v, eye_dist, lights = prepare(points, normals, material, eye, view_dir, lights)
    t = prepare_tangents(tangents, n)
    n, v = n.astype(np.float64), v.astype(np.float64)
    t = None if t is None else t.astype(np.float64)
    p = np.zeros_like(n) if p is None else p.astype(np.float64)
    term = material.brdf.classic if options.form == "classic" else material.brdf.eval_cos
    extra = eye_dist if options.attenuation_distance == "light+viewer" else None
    ambient = sum((light.radiant for light in lights if isinstance(light, AmbientLight)), np.zeros(3))
    colour = np.broadcast_to((material.emission + ambient * material.ambient) * options.scale, n.shape).copy()
    for light in lights:
        if isinstance(light, AmbientLight):
            continue
        for inc in light.incident(p, dtype=np.float64, extra_distance=extra):
            colour += term(n, inc.direction, v, tangent=t) * inc.irradiance
    return colour
