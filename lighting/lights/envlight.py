r"""The environment as a light of a scene: image-based lighting beside the punctual lights.

An :class:`EnvironmentLight` holds an environment (a lat-long image file, a procedural sky or a
constant radiance, with an intensity and a rotation about ``+z``) and answers what a renderer
asks of it: the light reflected at each shaded point, and the radiance seen behind the object.

Three ways to reflect it (``method``):

* ``"dominant"`` (default): the map's small, very bright regions (a sun) taken out as disk lights and
  shaded with the model's own BRDF, the rest by its exact irradiance map for diffuse lobes and by filtered
  importance sampling of its prefiltered levels for glossy ones
  (:func:`lighting.integrate.dominant.dominant_radiance`): within a few percent of the reference where the
  split sum is not (``lighting-explorer report accuracy --only ibl`` measures both), at the cost of
  16 lookups per glossy part and pixel (64 for a lobe narrower than 0.25 rad);
* ``"split-sum"``: the slides' form — SH9 irradiance for diffuse lobes, the prefiltered environment times
  the part's albedo for glossy ones (:func:`lighting.integrate.ibl.split_sum_radiance`); the
  environment is prefiltered once, on first use (``lighting-explorer bench --ibl`` times it), then every
  re-shade is a few lookups per pixel;
* ``"monte-carlo"``: the reference, multiple importance sampling with ``samples`` directions per
  point (:class:`lighting.integrate.ibl.ProgressiveRadiance`), seeded, so an image is reproducible.

The radiometric convention is the engine's (conventions.md): the light reflects the radiance
``L_o = ∫ f_r L_i (n·l) dω``; the classic form of the illumination equation is π times the
physical one, for this light as for the others (a white Lambert surface under a uniform sky of
radiance 1 is 1 in the physical form and π in the classic).
"""

from __future__ import annotations

import numpy as np

from .._text import quote
from .._validate import ArgumentTypeError, check_bool, check_choice, check_count
from .environment import Environment, as_environment

__all__ = ["ENVIRONMENT_METHODS", "DEFAULT_ENVIRONMENT_METHOD", "EnvironmentLight", "environment_terms",
           "split_environment_lights"]

#: How an :class:`EnvironmentLight` is reflected.
ENVIRONMENT_METHODS = ("dominant", "split-sum", "monte-carlo")
#: The method an :class:`EnvironmentLight` uses unless told otherwise (and a scene file's default).
DEFAULT_ENVIRONMENT_METHOD = "dominant"


class EnvironmentLight:
    """Light from every direction, from an environment; see the module notes.

    Parameters
    ----------
    environment : Environment, str, path, float or RGB
        An :class:`~lighting.lights.environment.Environment`; a file name (``.hdr``, ``.pfm``,
        ``.npy``, ``.exr``) or a sky name (:data:`lighting.lights.skies.SKIES`), read by
        :func:`lighting.lights.envfiles.load_environment`; or a constant radiance.
    intensity : float or RGB
        Multiplies the environment's radiance.
    rotation : float
        Turns the environment about ``+z`` by this many degrees (toward ``+φ``).
    background : bool
        Show the environment where the geometry does not cover the image.
    method : {"dominant", "split-sum", "monte-carlo"}
    samples : int
        Directions per point of ``"monte-carlo"`` (``"dominant"`` uses its own filtered-importance count,
        :data:`lighting.integrate.dominant.DOMINANT_SAMPLES`).
    seed : int
        Its seed.
    prefiltered : PrefilteredEnvironment, optional
        ``prefilter_environment()`` of the environment this light turns or scales (its base): reused,
        so a slider that makes a new light at every move does not prefilter again.

    Examples
    --------
    >>> from lighting.models.brdf import Lambert
    >>> light = EnvironmentLight(1.0)  # the white furnace: a uniform sky of radiance 1
    >>> light.reflected(Lambert(0.5), [[0, 0, 1.0]], [[0.6, 0, 0.8]]).round(6).tolist()
    [[0.5, 0.5, 0.5]]
    """

    is_environment = True

    def __init__(self, environment=1.0, *, intensity=1.0, rotation=0.0, background=True,
                 method=DEFAULT_ENVIRONMENT_METHOD, samples=64, seed=0, prefiltered=None):  # fmt: skip
        from .envfiles import load_environment

        self.source = environment
        self.environment = as_environment(load_environment(environment, intensity=intensity, rotation=rotation))
        self.intensity = intensity
        self.rotation = float(rotation)
        self.background = check_bool("background", background)
        self.method = check_choice("method", method, ENVIRONMENT_METHODS)
        self.samples = check_count("samples", samples, 2, 1 << 16)
        if not isinstance(seed, (int, np.integer)) or isinstance(seed, bool):
            raise ArgumentTypeError(f"seed must be an integer; got {quote(seed)}")
        self.seed = int(seed)
        self._prefiltered = None if prefiltered is None else prefiltered.for_environment(self.environment)

    def __repr__(self):
        extra = "".join(
            f", {k}={v!r}"
            for k, v, default in (
                ("intensity", self.intensity, 1.0),
                ("rotation", self.rotation, 0.0),
                ("background", self.background, True),
                ("method", self.method, DEFAULT_ENVIRONMENT_METHOD),
            )
            if not (np.all(np.asarray(v) == default) if k == "intensity" else v == default)
        )
        src = self.source if not isinstance(self.source, Environment) else type(self.source).__name__
        return f"EnvironmentLight({src!r}{extra})"

    @property
    def prefiltered(self):
        """The prefiltered environment (:func:`lighting.integrate.prefilter.prefilter_environment`), made once."""
        if self._prefiltered is None:
            from ..integrate.prefilter import prefilter_environment

            self._prefiltered = prefilter_environment(self.environment)
        return self._prefiltered

    def reflected(self, brdf, normals, view_dirs, *, split_terms: bool = False):
        """The radiance ``L_o`` a surface reflects toward ``view_dirs`` under this light (physical form).

        Parameters
        ----------
        brdf : BRDF
        normals, view_dirs : array_like, (N, 3)
            Unit normals and unit view vectors, world frame (``view_dirs`` may be one ``(3,)`` vector).
        split_terms : bool
            ``{"diffuse": ..., "specular": ...}`` instead of their sum (``"monte-carlo"`` gives its whole
            value as ``"specular"`` and zero ``"diffuse"``: the reference does not split).

        Returns
        -------
        ndarray, (N, 3) or dict
            In the dtype of the inputs.
        """
        from ..integrate.ibl import ProgressiveRadiance, split_sum_radiance

        if self.method == "split-sum":
            return split_sum_radiance(brdf, self.prefiltered, normals, view_dirs, split_terms=split_terms)
        if self.method == "dominant":
            from ..integrate.dominant import dominant_radiance

            return dominant_radiance(brdf, self.prefiltered, normals, view_dirs, split_terms=split_terms)
        n = np.asarray(normals)
        v = np.broadcast_to(np.asarray(view_dirs), n.shape)
        run = ProgressiveRadiance(brdf, self.environment, n, v, seed=self.seed)
        per_pass = max(2, min(self.samples, 16) // 2 * 2)
        while run.samples < self.samples:
            run.add(min(per_pass, max(2, (self.samples - run.samples) // 2 * 2)))
        value = run.value
        return {"diffuse": np.zeros_like(value), "specular": value} if split_terms else value

    def radiance(self, directions) -> np.ndarray:
        """The environment's radiance toward ``-directions``' sources: what a camera ray ``d`` sees behind.

        Parameters
        ----------
        directions : array_like, (..., 3)
            Ray directions, world frame.

        Returns
        -------
        ndarray, (..., 3)
        """
        return self.environment.radiance(directions)

    def to_dict(self) -> dict:
        """The light as a scene file's ``[[lights]]`` table (``type = "environment"``).

        Returns
        -------
        dict
        """
        if isinstance(self.source, Environment):
            raise ValueError("an EnvironmentLight made from an Environment object cannot be saved to a scene "
                             "file; make it from a file name, a sky name or a radiance")  # fmt: skip
        src = self.source
        out = {"type": "environment"}
        if isinstance(src, str) or hasattr(src, "__fspath__"):
            out["source"] = str(src)
        else:
            out["radiance"] = np.asarray(src, dtype=float).tolist()
        if not np.all(np.asarray(self.intensity) == 1):
            out["intensity"] = np.asarray(self.intensity, dtype=float).tolist()
        if self.rotation:
            out["rotation"] = self.rotation
        if not self.background:
            out["background"] = False
        if self.method != DEFAULT_ENVIRONMENT_METHOD:
            out["method"] = self.method
        if self.method == "monte-carlo":
            out["samples"] = self.samples
            out["seed"] = self.seed
        return out


def environment_terms(lights, brdf, normals, view, *, form="classic", terms=("diffuse", "specular"), dtype=None):
    """The diffuse and specular terms environment lights give at shaded samples, as the renderer adds them.

    Each light's physical ``L_o`` (:meth:`EnvironmentLight.reflected`), summed over the lights, times π in
    the classic form (conventions.md).

    Parameters
    ----------
    lights : sequence of EnvironmentLight
    brdf : BRDF
    normals : ndarray, (N, 3)
        Unit normals.
    view : ndarray, (N, 3) or (3,)
        Unit view vectors.
    form : {"classic", "physical"}
    terms : iterable of str
        The terms wanted; only ``"diffuse"`` and ``"specular"`` have a part here.
    dtype : float dtype, optional
        Of the results (default: the normals').

    Returns
    -------
    dict of str to ndarray
        ``(N, 3)`` per wanted term, in ``("diffuse", "specular")`` order; empty without lights or such terms.
    """
    names = [t for t in ("diffuse", "specular") if t in terms]
    if not lights or not names:
        return {}
    dt = np.dtype(normals.dtype if dtype is None else dtype).type
    v = np.broadcast_to(view, normals.shape)
    sums = {t: np.zeros(normals.shape, dtype=dt) for t in names}
    for light in lights:
        parts = light.reflected(brdf, normals, v, split_terms=True)
        for t in names:
            sums[t] += parts[t].astype(dt, copy=False)
    scale = dt(np.pi) if form == "classic" else dt(1)
    return {t: sums[t] * scale for t in names}


def split_environment_lights(lights):
    """``(other lights, environment lights)`` of a sequence of lights (order kept in each).

    Parameters
    ----------
    lights : sequence

    Returns
    -------
    list, list
    """
    if lights is None or isinstance(lights, (str, bytes, dict)) or not hasattr(lights, "__iter__"):
        return lights, []
    items = list(lights)
    env = [lt for lt in items if getattr(lt, "is_environment", False)]
    if not env:
        return lights, []
    return [lt for lt in items if not getattr(lt, "is_environment", False)], env
