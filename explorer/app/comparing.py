r"""Several BRDFs in the explorer: the comparison list's data, BRDF files, fitting, and the albedo curves.

The explorer keeps a :class:`~explorer.compare.BRDFList` beside the current model
(:attr:`ExplorerModel.compare <explorer.app.views.ExplorerModel>`).  What :class:`CompareMixin` adds to
the explorer model:

* :meth:`~CompareMixin.pin` — the current model with its current parameters (and the explorer's
  Lambert part, if it adds one) becomes an entry, labelled with the model and its parameters;
* :meth:`~CompareMixin.open_brdf` — a BRDF file (``.brdf``, MERL ``.binary``) becomes a registered
  model (:func:`lighting.files.file_model`): the current model, or an entry of the list;
* :meth:`~CompareMixin.fit` — an analytic model of :data:`FIT_MODELS` fitted to the current model by
  :func:`fit_model` (seconds: never in a drag), added as an entry: with a Lambert part beside it when the
  current model reflects diffusely (:func:`has_diffuse`), as a specular lobe alone cannot stand for a
  diffuse one;
* the overlays: the polar slice and the θ_v, θ_h, θ_d curves of every *shown* entry (its colour, the
  same terms and plot options as the current model), cached per entry, so only a new light angle or
  new plot options recompute them;
* the albedo curves: ``ρ(θ_v)`` at :data:`ALBEDO_ANGLES_DEG` of the current model and of each shown
  entry, by :func:`lighting.integrate.albedo_curve` (quadrature, with its error and the 2 % flag),
  cached per entry and per material (they do not depend on the light);
* the split sphere's other half: the solo entry, else the first shown (:meth:`~CompareMixin.split_target`).

Nothing here imports PyVista or Matplotlib.

Example
-------
>>> from explorer.app.views import ExplorerModel
>>> model = ExplorerModel(sphere_size=32, mesh_size=32, lobe_resolution=8)
>>> model.state.update(model="phong", shininess=20.0) and None
>>> model.pin().label
'Phong e=20 k_s=0.5'
>>> model.state.shininess = 200.0
>>> _ = model.update()
>>> [(o.label, o.colour) for o in model.views["polar"].overlays]
[('Phong e=20 k_s=0.5', '#E69F00')]
"""

from __future__ import annotations

import math
import operator
import os
from dataclasses import dataclass
from functools import reduce

import numpy as np

from lighting import Lambert
from lighting.analysis import polar_slice, theta_d_curve, theta_h_curve, theta_v_curve
from lighting.analysis.machband import LUMA
from lighting.integrate import albedo_curve
from lighting.models import BRDFFlags

from ..compare import FIT_MODELS, BRDFList
from .params import model_label, offered_parameters
from .state import MAX_ENTRIES, PANELS

__all__ = [
    "PANELS",
    "FIT_MODELS",
    "ALBEDO_ANGLES_DEG",
    "CURVE_SAMPLES",
    "MAX_ENTRIES",
    "Overlay",
    "AlbedoCurveView",
    "restrict",
    "pin_label",
    "has_diffuse",
    "fit_model",
    "CompareMixin",
]

#: The view angles of the albedo curves, degrees: 0° … 88° in 2° steps and 89°.  At 90° the view is on
#: the horizon, where every BRDF is 0 by the engine's convention (so ρ = 0 there, for Lambert too).
ALBEDO_ANGLES_DEG = np.append(np.arange(0.0, 89.0, 2.0), 89.0)
#: Quadrature nodes per albedo value of the curves (the readout's count).
CURVE_SAMPLES = 4096
#: Short names of parameters in labels (the controls' names, shortened).
_SHORT = {"shininess": "e", "roughness": "α", "alpha_x": "α_x", "alpha_y": "α_y", "sigma": "σ", "ks": "k_s",
          "f0": "F0", "kd": "k_d", "rs": "R_s", "nu": "n_u", "nv": "n_v"}  # fmt: skip


@dataclass(frozen=True, eq=False)
class Overlay:
    """One entry's curve in a plot: ``values`` against ``angles`` (rad), drawn in ``colour``."""

    label: str
    colour: str
    key: int
    angles: np.ndarray
    values: np.ndarray


@dataclass(frozen=True, eq=False)
class AlbedoCurveView:
    """``ρ(θ_v)`` of one BRDF in the plotted channel, with its error and the 2 % flag.

    ``colour`` is ``None`` for the current model (drawn white).  ``value`` and ``error`` are the
    channel's (luminance: the Rec. 709 weights of the RGB values and errors, as the readout);
    ``unconverged`` is :attr:`lighting.integrate.AlbedoCurve.unconverged` of the channel (luminance:
    of any channel).
    """

    label: str
    colour: str | None
    theta: np.ndarray
    value: np.ndarray
    error: np.ndarray
    unconverged: np.ndarray
    samples: int
    method: str


def restrict(brdf, terms):
    """The parts of ``brdf`` whose ``term`` is in ``terms`` (their sum; ``Lambert(0)`` if none).

    The comparison entries follow the term switches as the current model does
    (:meth:`~explorer.app.state.AppState.brdf`): the explorer's Lambert part is ``"diffuse"``, the model
    its own term.

    Parameters
    ----------
    brdf : BRDF
        A model or a sum.
    terms : collection of str
        ``"diffuse"`` and/or ``"specular"`` (``"ambient"`` is no part of a BRDF).

    Returns
    -------
    BRDF

    Examples
    --------
    >>> from lighting import Phong
    >>> restrict(Lambert(0.5) + Phong(0.5, 20.0), ("specular",))
    Phong(ks=0.5, shininess=20)
    """
    parts = [p for p in brdf.parts if p.flags & BRDFFlags.of_terms(terms)]
    if len(parts) == len(brdf.parts):
        return brdf
    return reduce(operator.add, parts) if parts else Lambert(0.0)


def _short(value) -> str | None:
    if isinstance(value, bool) or value is None:
        return None
    if isinstance(value, (tuple, list)):
        if max(value) - min(value) > 1e-12:
            return None  # a colour: too long for a label
        value = value[0]
    if isinstance(value, (int, float)):
        return f"{value:.3g}"
    return None


def pin_label(state) -> str:
    """The label of the current model pinned to the list: its name and its numbers (at most three).

    Parameters
    ----------
    state : AppState
        The explorer's controls.

    Returns
    -------
    str
        E.g. ``"Cook-Torrance α=0.3 F0=0.04"``; a choice that differs from its default is added
        (``"ggx"``).

    Examples
    --------
    >>> from explorer.app.state import AppState
    >>> pin_label(AppState(model="cook-torrance", ndf="ggx"))
    'Cook-Torrance α=0.3 ggx k_s=1 F0=0.04'
    """
    words = []
    numbers = 0
    # The lobe's shape first (exponent, roughness), then the colours' grey values.
    for p in sorted(offered_parameters(state.model), key=lambda p: p.kind == "color"):
        value = state.param(p.name)
        if p.kind in ("float", "color"):
            text = _short(value)
            if text is not None and numbers < 3:
                words.append(f"{_SHORT.get(p.name, p.name)}={text}")
                numbers += 1
        elif p.kind == "choice" and value != p.default:
            words.append(str(value))
    label = model_label(state.model)
    return " ".join([label, *words]) if words else label


def has_diffuse(brdf) -> bool:
    """Whether ``brdf`` has a diffuse part: a part whose term is ``"diffuse"`` or that carries its own diffuse.

    Models read from a file (``BRDFFlags.OWN_DIFFUSE``: measured data and BRDF Explorer files are the whole material)
    count as having one, as their data may hold it.

    Parameters
    ----------
    brdf : BRDF
        A model or a sum.

    Returns
    -------
    bool

    Examples
    --------
    >>> from lighting import BlinnPhong
    >>> has_diffuse(Lambert(0.5) + BlinnPhong(0.5, 32.0)), has_diffuse(BlinnPhong(0.5, 32.0))
    (True, False)
    """
    return any(p.flags & (BRDFFlags.DIFFUSE | BRDFFlags.OWN_DIFFUSE) for p in brdf.parts)


def fit_model(name: str, target, *, n_theta: int = 12, n_phi: int = 16, max_theta_deg: float = 85.0):
    """Fit the analytic model ``name`` of :data:`FIT_MODELS` to ``target``; with a Lambert part if it has a diffuse one.

    A target with a diffuse part (:func:`has_diffuse`) is fitted by ``Lambert(k_d) + model``
    (:func:`lighting.analysis.fit.fit_brdf` with ``lambert=True``): a specular lobe alone, fitted to a
    surface that is mostly diffuse, comes out a broad lobe standing for the diffuse part too (GGX α 0.64
    for the explorer's default surface, whose highlight alone wants 0.33), which the term switches cannot
    take apart.  A target without one is fitted by the model alone.

    Parameters
    ----------
    name : str
        A key of :data:`FIT_MODELS`.
    target : BRDF
        The model to fit.
    n_theta, n_phi, max_theta_deg
        The direction pairs compared (:func:`lighting.analysis.audit.direction_pairs`).

    Returns
    -------
    FitResult
        As :func:`~lighting.analysis.fit.fit_brdf`; with a Lambert part, ``model`` is the sum and
        ``parameters`` and ``errors`` hold ``kd`` beside the model's own.
    """
    from lighting.analysis.fit import fit_brdf

    if name not in FIT_MODELS:
        raise ValueError(f"fit must be one of {', '.join(FIT_MODELS)}; got {name!r}")
    model, fixed, _ = FIT_MODELS[name]
    return fit_brdf(model, target, fixed=dict(fixed), n_theta=n_theta, n_phi=n_phi, max_theta_deg=max_theta_deg,
                    lambert=has_diffuse(target))  # fmt: skip


class CompareMixin:
    """The comparison list of :class:`~explorer.app.views.ExplorerModel`: entries, overlays, albedo curves, fits."""

    def _init_compare(self, compare):
        if compare is not None and not isinstance(compare, BRDFList):
            raise TypeError(f"compare must be an explorer.compare.BRDFList; got {type(compare).__name__}")
        self.compare = compare if compare is not None else BRDFList(max_entries=MAX_ENTRIES)
        self._overlay_cache: dict = {}
        self._albedo_cache: dict = {}
        self._current_curve = (None, None)

    # ------------------------------------------------------------------ actions
    def pin(self, label: str | None = None):
        """Add the current model, with its current parameters, to the comparison list.

        The entry is the surface's BRDF (:meth:`~explorer.app.state.AppState.brdf`: the model, plus
        the explorer's ``Lambert(k_d × colour)`` if it adds one), so it stays what it was when the
        controls move on.

        Parameters
        ----------
        label : str, optional
            Default :func:`pin_label`.

        Returns
        -------
        Entry
            The new entry (``ValueError`` when the list is full).
        """
        return self.compare.add(self.state.brdf(), label or pin_label(self.state))

    def open_brdf(self, path, *, current: bool = True) -> str:
        """Open a BRDF file as a registered model: the current model, or (``current=False``) an entry.

        Parameters
        ----------
        path : str or os.PathLike
            A ``.brdf`` or MERL ``.binary`` file.
        current : bool
            Make it the current model (its parameters become the model's controls); else add
            it, with its file's default parameters, to the comparison list.

        Returns
        -------
        str
            The name it is registered under (:func:`lighting.files.file_model`, e.g. ``"gold-paint"``).

        Raises
        ------
        ValueError
            A bad file (the reader's one-line message, naming the file), or a full list.
        """
        from lighting.files import file_model

        if not current and len(self.compare) >= self.compare.max_entries:
            raise ValueError(f"the comparison holds at most {self.compare.max_entries} BRDFs; remove one first")
        cls = file_model(path, register=True)
        if current:
            self.state.update(model=cls.name)
        else:
            self.compare.add(cls(), os.path.basename(os.fspath(path)))
        return cls.name

    def fit(self, fit: str | None = None):
        """Fit an analytic model to the current model and add it to the list, labelled with its residual.

        The target is the surface's BRDF (:meth:`~explorer.app.state.AppState.brdf`); the fit is
        :func:`fit_model` (cosine-weighted least squares, a second or more): ``Lambert(k_d) +`` the model
        when the target has a diffuse part, labelled ``"… + Lambert"``.

        Parameters
        ----------
        fit : str, optional
            A name of :data:`FIT_MODELS`; default the ``fit`` control.

        Returns
        -------
        (Entry, FitResult)
            The new entry and the fit.
        """
        name = self.state.fit if fit is None else fit
        if name not in FIT_MODELS:
            raise ValueError(f"fit must be one of {', '.join(FIT_MODELS)}; got {name!r}")
        if len(self.compare) >= self.compare.max_entries:
            raise ValueError(f"the comparison holds at most {self.compare.max_entries} BRDFs; remove one first")
        short = FIT_MODELS[name][2]
        target = self.state.brdf()
        result = fit_model(name, target)
        p = result.parameters
        shape = next((f"{_SHORT[k]}={p[k]:.3g}" for k in ("roughness", "alpha_x", "shininess") if k in p), "")
        diffuse = " + Lambert" if has_diffuse(target) else ""
        label = f"{short} fit {shape}{diffuse} (rel. rms {result.relative_rms:.3f})".replace("  ", " ")
        return self.compare.add(result.model, label), result

    def split_target(self):
        """The entry the split sphere shows on its right half: the solo entry, else the first shown (or None).

        Returns
        -------
        Entry or None
        """
        shown = self.compare.shown()
        return shown[0] if shown else None

    # ------------------------------------------------------------------ what the views depend on
    def _compare_inputs(self) -> dict:
        target = self.split_target() if self.state.split else None
        return {
            "compare": tuple((e.key, e.colour, e.label) for e in self.compare.shown()),
            "split_target": None if target is None else target.key,
        }

    def _prune(self):
        keys = {e.key for e in self.compare}
        for cache in (self._overlay_cache, self._albedo_cache):
            for k in [k for k in cache if k[0] not in keys]:
                del cache[k]

    # ------------------------------------------------------------------ overlays
    def _overlays(self, kind: str, theta: float, opts: dict) -> tuple:
        """The curves of ``kind`` (``"polar"``, ``"theta_v"``, ``"theta_h"``, ``"theta_d"``) of the shown entries."""
        s = self.state
        phi = math.radians(s.phi)
        self._prune()
        out = []
        for e in self.compare.shown():
            where = None if kind == "theta_d" else round(theta, 12)
            key = (e.key, kind, tuple(s.terms), where, s.phi, s.lock if kind == "polar" else None,
                   tuple(sorted(opts.items())))  # fmt: skip
            data = self._overlay_cache.get(key)
            if data is None:
                brdf = restrict(e.brdf, s.terms)
                if kind == "polar":
                    c = polar_slice(brdf, theta, fixed="light", phi_in=phi, n=361, lock=s.lock, **opts)
                elif kind == "theta_v":
                    c = theta_v_curve(brdf, theta, phi_l=phi, n=181, **opts)
                elif kind == "theta_h":
                    c = theta_h_curve(brdf, theta_d=theta, phi_h=phi, n=181, **opts)
                else:
                    c = theta_d_curve(brdf, theta_h=0.0, phi_h=phi, n=181, **opts)
                data = (np.asarray(c.angles, dtype=np.float64), np.asarray(c.values, dtype=np.float64))
                self._overlay_cache[key] = data
            out.append(Overlay(e.label, e.colour, e.key, *data))
        return tuple(out)

    # ------------------------------------------------------------------ albedo curves
    def _curve(self, brdf):
        return albedo_curve(brdf, np.radians(ALBEDO_ANGLES_DEG), samples=CURVE_SAMPLES, method="quadrature")

    def _albedo_curves(self, brdf) -> tuple:
        """``ρ(θ_v)`` of the current model (``brdf``, the plotted parts) and of each shown entry."""
        s = self.state
        self._prune()
        material = (s.model, tuple(s.params.items()), s.kd, s.color, tuple(s.terms))
        if self._current_curve[0] != material:
            self._current_curve = (material, self._curve(brdf))
        curves = [(f"{model_label(s.model)} (current)", None, self._current_curve[1])]
        for e in self.compare.shown():
            key = (e.key, tuple(s.terms))
            if key not in self._albedo_cache:
                self._albedo_cache[key] = self._curve(restrict(e.brdf, s.terms))
            curves.append((e.label, e.colour, self._albedo_cache[key]))
        return tuple(self._channel_curve(label, colour, c) for label, colour, c in curves)

    def _channel_curve(self, label, colour, c) -> AlbedoCurveView:
        ch = self.state.channel
        albedo = np.asarray(c.albedo, dtype=np.float64)
        error = np.abs(np.asarray(c.error, dtype=np.float64))
        flags = np.asarray(c.unconverged)
        if ch == "luminance":
            value, err, flag = albedo @ LUMA, error @ LUMA, flags.any(axis=-1)
        else:
            k = "rgb".index(ch)
            value, err, flag = albedo[:, k], error[:, k], flags[:, k]
        return AlbedoCurveView(label, colour, np.asarray(c.theta, dtype=np.float64), value, err, flag,
                               int(c.samples), c.method)  # fmt: skip
