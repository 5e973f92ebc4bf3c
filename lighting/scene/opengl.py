"""OpenGL materials in scenes: on the engine's classic form under engine lights, term by term under OpenGL lights."""

from __future__ import annotations

from dataclasses import replace

from ..models import BlinnPhong, Lambert
from ..shading import opengl as gl
from ..shading.equation import Material

__all__ = ["gl_material_to_engine"]


def gl_material_to_engine(material: gl.Material) -> Material:
    """An OpenGL material on the engine's classic form.

    ``Lambert(d_cm) + BlinnPhong(s_cm, s_rm)`` (unnormalized, the slides' and
    OpenGL's ``k_s (n·h)^e``), ambient ``k_a = a_cm``, emission ``k_e = e_cm``;
    alpha is dropped.  Under an engine light of colour ``I`` this gives
    ``k_d I (n·l) + k_s I (n·h)^e`` — OpenGL's bracket with ``d_cli = s_cli = I``.

    Parameters
    ----------
    material : lighting.shading.opengl.Material
        The OpenGL material.

    Returns
    -------
    lighting.shading.equation.Material
        The engine material.

    Examples
    --------
    >>> m = gl_material_to_engine(gl.Material(diffuse=(0.5, 0.5, 0.5), specular=(1, 1, 1), shininess=20))
    >>> m.brdf
    Lambert(kd=0.5) + BlinnPhong(ks=1, shininess=20)
    """
    if not isinstance(material, gl.Material):
        raise ValueError(f"material must be a lighting.shading.opengl.Material; got {type(material).__name__}")
    brdf = Lambert(material.diffuse[:3]) + BlinnPhong(material.specular[:3], material.shininess, normalized=False)
    return Material(brdf, ambient=material.ambient[:3], emission=material.emission[:3])


def _gl_with_terms(material: gl.Material, terms) -> gl.Material:
    """Keep only the chosen terms: each term of the GL equation is linear in one material colour."""
    zero = (0.0, 0.0, 0.0, 1.0)
    keep = {"emission": "emission", "ambient": "ambient", "diffuse": "diffuse", "specular": "specular"}
    changes = {attr: zero for t, attr in keep.items() if t not in terms}
    if "diffuse" in changes:  # the vertex alpha is the diffuse alpha: keep it
        changes["diffuse"] = (0.0, 0.0, 0.0, material.diffuse[3])
    return replace(material, **changes) if changes else material


def _engine_material(material):
    """``material`` as the engine shades it: an OpenGL material mapped by :func:`gl_material_to_engine`."""
    return gl_material_to_engine(material) if isinstance(material, gl.Material) else material
