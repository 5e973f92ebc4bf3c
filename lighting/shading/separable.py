r"""The separable forms: the shading pass's optional extension of the model protocol.

A shading pass sums ``f_r (n·l)`` (or the classic ``π f_r (n·l)``) times each light's colour over
many points and lights.  Most models are a few scalar lobes times RGB constants, ``Σ_k s_k c_k``
(``k_d`` times ``n·l/π``, ``k_s`` times a specular lobe), so the pass can weight colours once per term
instead of once per point and channel.  A model that offers this form implements :class:`Separable`;
any other model is shaded channel by channel from its ``eval_cos_geometry``/``classic_geometry``
(:func:`terms` does either), with the same numbers.

A separable model may also say it is ``stackable``: its forms then accept a
:class:`~lighting.shading.stacked.StackedGeometry`, every distant light over every point at once as
``(K, N)`` planes.  Such a model reads only the derived quantities (``n_dot_l``, ``n_dot_h``,
``one_minus_r_dot_v`` …) and the geometry's own forms — ``log_n_dot_h_power(exponent, dtype)``, which a
stacked geometry computes from ``tan²θ_h``, and ``refine(values, dtype, evaluate)``, which
re-evaluates on a plain :class:`~lighting.models.geometry.Geometry` the entries a stacked geometry's
fast forms do not serve — never the vectors themselves, and never asks which geometry it was given.

The built-in analytic models implement the extension through
:class:`lighting.models.base.SeparableBRDF`, which derives their ``eval_cos`` and ``classic`` from
the same terms.

Examples
--------
>>> import numpy as np
>>> from lighting.models.brdf import Geometry, Lambert
>>> g = Geometry(np.array([0.0, 0.0, 1.0]), np.array([0.0, 0.6, 0.8]), np.array([0.0, 0.0, 1.0]))
>>> [(float(s), c.tolist()) for s, c in terms(Lambert(0.5), g, "classic")]
[(0.8, [0.5, 0.5, 0.5])]
>>> is_separable(Lambert()), stacks(Lambert())
(True, True)
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np

__all__ = ["Separable", "is_separable", "stacks", "terms"]

_UNIT_RGB = np.eye(3)


@runtime_checkable
class Separable(Protocol):
    """A model whose values are ``Σ_k s_k c_k``: scalar fields ``s_k`` times RGB constants ``c_k``.

    Attributes
    ----------
    stackable : bool
        Whether the separable forms accept a :class:`~lighting.shading.stacked.StackedGeometry`
        (an instance may answer for itself: an anisotropic lobe needs tangents, which a stacked
        geometry does not carry).
    """

    stackable: bool

    def separable_cos(self, g) -> list[tuple[np.ndarray, np.ndarray]]:
        """``f_r (n·l)`` as pairs ``(s_k, c_k)``: a scalar field in the dtype of ``g`` and an RGB constant ``(3,)``.

        ``g`` is a :class:`~lighting.models.geometry.Geometry`, or a stacked one if :attr:`stackable`.
        """

    def separable_classic(self, g) -> list[tuple[np.ndarray, np.ndarray]]:
        """The classic term ``π f_r (n·l)`` in the form of :meth:`separable_cos`."""


def is_separable(model) -> bool:
    """Whether ``model`` implements :class:`Separable` (both forms).

    Parameters
    ----------
    model : BRDF
        One model (a part of a sum, or a sum).

    Returns
    -------
    bool
    """
    return callable(getattr(model, "separable_cos", None)) and callable(getattr(model, "separable_classic", None))


def stacks(model) -> bool:
    """Whether ``model``'s separable forms accept a stacked geometry (all distant lights at once).

    Parameters
    ----------
    model : BRDF
        One model.

    Returns
    -------
    bool
        ``False`` for a model without separable forms.
    """
    return is_separable(model) and bool(getattr(model, "stackable", False))


def terms(model, g, form: str) -> list[tuple[np.ndarray, np.ndarray]]:
    """``f_r (n·l)`` (``form="cos"``) or ``π f_r (n·l)`` (``"classic"``) of ``model`` as ``[(s_k, c_k), ...]``.

    A :class:`Separable` model gives its own terms; any other gives its three channels, each with a unit
    RGB constant.

    Parameters
    ----------
    model : BRDF
        One model.
    g : Geometry or StackedGeometry
        The shading directions (a stacked one only if :func:`stacks` says so).
    form : str
        ``"classic"`` for ``π f_r (n·l)``; any other (``"cos"``, the shading options' ``"physical"``) for
        ``f_r (n·l)``.

    Returns
    -------
    list of (ndarray, ndarray)
        Scalar fields in the dtype of ``g`` and RGB constants ``(3,)``.
    """
    if is_separable(model):
        return model.separable_classic(g) if form == "classic" else model.separable_cos(g)
    f = model.classic_geometry(g) if form == "classic" else model.eval_cos_geometry(g)
    return [(f[..., i], _UNIT_RGB[i]) for i in range(3)]
