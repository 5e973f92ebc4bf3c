r"""Models defined in Python: a function of ``(n, l, v)`` and a parameter table, registered like a built-in.

For a notebook or a lecture exercise: write ``f_r`` as a NumPy function, give its parameters, and the
engine treats it as any other model — ``eval``/``eval_cos``/``classic``, plots, albedo, the audit,
scene files and the explorer's generated controls.  The engine knows nothing of its lobe, so it
integrates over the whole hemisphere and samples the cosine-weighted hemisphere (unbiased, slow for
sharp lobes); :meth:`summary` says so.

Examples
--------
>>> import numpy as np
>>> from lighting.models import Parameter, define_brdf
>>> def minnaert(n, l, v, *, kd, k):
...     nl = np.sum(n * l, axis=-1, keepdims=True)
...     nv = np.sum(n * v, axis=-1, keepdims=True)
...     return kd / np.pi * (nl * nv) ** (k - 1)
>>> Minnaert = define_brdf("minnaert", minnaert, [
...     Parameter("kd", "color", 0.5, high=1.0, description="albedo at k = 1"),
...     Parameter("k", "float", 1.0, low=1.0, high=8.0, description="limb darkening")], register=False)
>>> m = Minnaert(kd=0.8, k=1.0)
>>> float(m.eval([0, 0, 1], [0, 0.6, 0.8], [0, 0, 1])[0]) == 0.8 / np.pi
True
>>> m.summary()
'minnaert kd=0.8 k=1 (Python function; cosine sampling)'
"""

from __future__ import annotations

import numpy as np

from ..numerics import saturate_to
from .base import BRDF, BRDFFlags
from .protocol import Parameter, register_model

__all__ = ["define_brdf"]


class PythonBRDF(BRDF):
    """Base of the classes :func:`define_brdf` makes: ``f_r`` from a Python function of ``(n, l, v)``."""

    #: The user's function ``f(n, l, v, **parameters)``; set on each defined class.
    function = None

    def __init__(self, **values):
        table = {p.name: p for p in self.parameters}
        unknown = sorted(set(values) - set(table))
        if unknown:
            raise ValueError(f"{self.name or type(self).__name__}: unknown parameter {unknown[0]!r}; "
                             f"allowed: {', '.join(table) or '(none)'}")  # fmt: skip
        for name, p in table.items():
            value = p.check(values.get(name, p.default))
            if p.kind == "color":
                value = np.broadcast_to(np.asarray(value, dtype=np.float64), (3,)).copy()
            setattr(self, name, value)

    def _params(self):
        return {p.name: getattr(self, p.name) for p in self.parameters}

    def summary(self) -> str:
        """The name, the parameters and how the engine treats the function.

        Returns
        -------
        str
        """
        def text(x):
            x = np.asarray(x)
            return f"{float(x.reshape(-1)[0]):g}" if x.size == 1 or np.all(x == x.reshape(-1)[0]) else str(x.tolist())

        values = " ".join(f"{p.name}={text(getattr(self, p.name))}" for p in self.parameters)
        return f"{self.name or type(self).__name__} {values} (Python function; cosine sampling)".replace("  ", " ")

    def _f(self, g):
        return saturate_to(self._f64(g), g.dtype)

    def _f64(self, g):
        values = {p.name: getattr(self, p.name) for p in self.parameters}
        with np.errstate(all="ignore"):  # below the horizon the function may take roots of negatives: masked next
            raw = type(self).function(g.n, g.l, g.v, **values)
        try:
            f = np.broadcast_to(np.asarray(raw, dtype=np.float64), np.shape(g.n_dot_l) + (3,))
        except (TypeError, ValueError):
            raise ValueError(f"{self.name}: the function must return f_r of shape (..., 3) or (..., 1) for "
                             f"{np.shape(g.n_dot_l)} direction pairs; got {type(raw).__name__} of shape "
                             f"{np.shape(raw)}") from None  # fmt: skip
        f = np.where(g.above[..., None], f, 0.0)
        bad = np.any(~np.isfinite(f) | (f < 0), axis=-1)
        if np.any(bad):
            raise ValueError(f"{self.name}: the function returned negative or non-finite f_r at "
                             f"{int(np.count_nonzero(bad))} direction pairs above the horizon; f_r must be finite "
                             "and >= 0")  # fmt: skip
        return f

    def _f_cos(self, g):
        # f_r (n·l) in float64, then the dtype, saturating (a huge f_r in float32 is its largest value).
        nl = np.maximum(np.asarray(g.n_dot_l, dtype=np.float64), 0.0)
        return saturate_to(self._f64(g) * nl[..., None], g.dtype)


def define_brdf(name: str, function, parameters=(), *, term: str = "specular", register: bool = True):
    """A model class from a Python function of ``(n, l, v)`` and a parameter table.

    Parameters
    ----------
    name : str
        The model's name in scene files, the command line and the explorer (lower case, ``-`` between
        words).
    function : callable
        ``function(n, l, v, **parameters)`` → ``f_r`` in 1/sr: ``n``, ``l``, ``v`` are unit vectors of
        shape ``(..., 3)`` (float64 or float32), each parameter a float, bool, str or an RGB array
        ``(3,)``; it returns an array broadcastable to ``(..., 3)`` (``(..., 1)`` for grey).  It is called
        for pairs above the horizon and below it; the engine sets the values below to 0.
    parameters : sequence of Parameter
        The parameter table (:class:`~lighting.models.protocol.Parameter`), in the order of the
        function's keywords; the explorer builds its controls from it.
    term : {"specular", "diffuse"}
        Which term of the slides' decomposition the model is.
    register : bool
        Register it (:func:`~lighting.models.protocol.register_model`) so scene files and the explorer
        find it by ``name``.

    Returns
    -------
    type
        A :class:`~lighting.models.base.BRDF` subclass; its constructor takes the parameters as keywords
        (each checked by its table row).

    Raises
    ------
    ValueError
        A name already registered (with ``register=True``), a table that is not of ``Parameter`` rows, or
        a ``term`` other than the two.

    Notes
    -----
    The engine knows nothing of the function's lobe: ``lobe()`` is ``None`` (quadrature covers the
    hemisphere about the normal; plots measure the lobe numerically) and ``sampler()`` is the
    cosine-weighted hemisphere — unbiased for any finite ``f_r``, slow for sharp lobes.  A model that
    needs better is a :class:`~lighting.models.base.BRDF` subclass of its own with ``lobe()`` and
    ``sampler()``.  The function's values are checked on every call: a negative, NaN or infinite
    ``f_r`` above the horizon is a ``ValueError`` naming the model.

    Examples
    --------
    >>> import numpy as np
    >>> from lighting.models import Parameter, define_brdf
    >>> Flat = define_brdf("flat-grey", lambda n, l, v, *, kd: kd / np.pi * np.ones(np.shape(n)),
    ...                    [Parameter("kd", "float", 0.5, high=1.0)], term="diffuse", register=False)
    >>> round(float(Flat(kd=0.5).eval([0, 0, 1], [0, 0, 1], [0, 0, 1])[0]), 6)
    0.159155
    """
    if not isinstance(name, str) or not name or name != name.strip().lower():
        raise ValueError(f"define_brdf: name must be a non-empty lower-case string; got {name!r}")
    if not callable(function):
        raise TypeError(f"define_brdf: function must be callable; got {type(function).__name__}")
    rows = tuple(parameters)
    if not all(isinstance(p, Parameter) for p in rows):
        raise ValueError("define_brdf: parameters must be a sequence of lighting.models.Parameter rows")
    if term not in ("specular", "diffuse"):
        raise ValueError(f"define_brdf: term must be 'specular' or 'diffuse'; got {term!r}")
    cls = type(
        "".join(w.capitalize() for w in name.replace("_", "-").split("-")) or "PythonModel",
        (PythonBRDF,),
        {"name": name, "parameters": rows, "flags": BRDFFlags.of_term(term), "function": staticmethod(function),
         "__doc__": getattr(function, "__doc__", None) or f"The Python-defined model {name!r}."},
    )  # fmt: skip
    if register:
        register_model(cls)
    return cls
