r"""A model's controls, generated from its parameter table (as BRDF Explorer builds sliders from a file's block).

Every registered model describes its constructor's keywords in ``cls.parameters``
(:class:`lighting.models.protocol.Parameter`: kind ``float``/``color``/``bool``/``choice``, range, slider
range, log scale, unit, description).  The explorer offers one control per row:

* ``float`` — a slider over ``Parameter.control_range`` (log10 of it when ``log``); a parameter whose
  default is ``None`` (``alpha_y``: "None = α_x") also gets a check box that sets ``None`` back;
* ``color`` — a slider for a grey value (RGB values from a scene file or the command line are kept
  until the slider moves);
* ``bool`` — a check box; ``choice`` — a row of buttons, one of them on.

Two rows are not offered: the fixed arguments of a variant (``blinn-phong-normalized`` fixes
``normalized``), and the *diffuse colour* of a model that carries its own diffuse reflection
(:func:`carries_diffuse`), which the explorer's ``k_d`` and surface colour fill — for such a model the
explorer adds no Lambert part of its own (Oren–Nayar, Disney and Ashikhmin–Shirley would otherwise
count diffuse twice).  Nothing here imports PyVista or Matplotlib.

Example
-------
>>> [p.name for p in offered_parameters("oren-nayar")]
['sigma', 'form']
>>> validate_parameter(parameter_table("phong")["shininess"], -1)
Traceback (most recent call last):
...
ValueError: shininess must be a number in [0, inf); got -1
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence

import numpy as np

from lighting.models import BRDFFlags, model_variants

__all__ = [
    "MODELS",
    "MODEL_LABELS",
    "model_choices",
    "model_label",
    "kd_label",
    "carries_diffuse",
    "diffuse_parameter",
    "parameter_table",
    "offered_parameters",
    "parameter_defaults",
    "validate_parameter",
    "slider_range",
    "none_label",
    "implied_parameters",
    "conductor_none_value",
]


def model_choices() -> tuple[str, ...]:
    """The explorer's model list now: every registered model and named variant, in registration order.

    Returns
    -------
    tuple of str
        ``tuple(MODELS)``, e.g. ``("lambert", "phong", "blinn-phong", "blinn-phong-normalized",
        "cook-torrance")`` for the built-in models.
    """
    return tuple(model_variants())


def model_label(name: str) -> str:
    """The label a model list shows for a registered model or variant name.

    Each word of the model's own name is capitalized (``"cook-torrance"`` → ``"Cook-Torrance"``);
    a variant adds the rest of its name in words (``"blinn-phong-normalized"`` →
    ``"Blinn-Phong normalized"``).  A model read from a BRDF file keeps the file's own name, as its
    author wrote it: ``"ggx-copper (file)"`` for ``ggx-copper.brdf``.

    Parameters
    ----------
    name : str
        A name of :func:`lighting.models.model_variants`.

    Returns
    -------
    str
        The label.

    Examples
    --------
    >>> [model_label(m) for m in ("lambert", "blinn-phong", "blinn-phong-normalized")]
    ['Lambert', 'Blinn-Phong', 'Blinn-Phong normalized']
    """
    entry = model_variants().get(name)
    path = getattr(entry[0], "file_path", "") if entry is not None else ""
    if path:
        return f"{os.path.splitext(os.path.basename(path))[0]} (file)"
    base = entry[0].name if entry is not None and entry[0].name else name
    if name != base and name.startswith(base + "-"):
        return model_label(base) + " " + name[len(base) + 1 :].replace("-", " ")
    return "-".join(word[:1].upper() + word[1:] for word in name.split("-"))


class _ModelList(Sequence):
    """The names of the registered models and variants, read from the registry at each use.

    A model registered after the explorer was imported is in the list (and so among the choices of
    the ``model`` control, the command line's ``--model`` and the ``m`` key) from then on.
    """

    def __getitem__(self, index):
        return tuple(model_variants())[index]

    def __len__(self) -> int:
        return len(model_variants())

    def __contains__(self, name) -> bool:
        return name in model_variants()

    def __eq__(self, other):
        return tuple(self) == (tuple(other) if isinstance(other, Sequence) else other)

    def __hash__(self):
        return hash(tuple(self))

    def __repr__(self) -> str:
        return repr(tuple(self))


class _ModelLabels(Mapping):
    """:func:`model_label` of every name of :data:`MODELS`, as a mapping (read from the registry at each use)."""

    def __getitem__(self, name):
        if name not in MODELS:
            raise KeyError(name)
        return model_label(name)

    def __iter__(self):
        return iter(MODELS)

    def __len__(self) -> int:
        return len(MODELS)


#: The model list: every registered model and named variant, in registration order
#: (:func:`lighting.models.model_variants`; the built-in ones in the lectures' order).
MODELS = _ModelList()
MODEL_LABELS = _ModelLabels()


def _entry(model: str):
    entry = model_variants().get(model)
    if entry is None:
        raise ValueError(f"model {model!r} is not registered; models: {', '.join(model_variants())}")
    return entry


def carries_diffuse(cls) -> bool:
    """Whether a model class reflects diffusely itself, so that the explorer adds no Lambert part to it.

    True for a diffuse model (``BRDFFlags.DIFFUSE``: Lambert, Oren–Nayar) and for one that declares its
    own diffuse term (``BRDFFlags.OWN_DIFFUSE``: Disney, Ashikhmin–Shirley's coupled diffuse).

    Parameters
    ----------
    cls : type
        A :class:`~lighting.models.brdf.BRDF` subclass.

    Returns
    -------
    bool
    """
    return bool(cls.flags & (BRDFFlags.DIFFUSE | BRDFFlags.OWN_DIFFUSE))


def kd_label(model: str) -> str:
    """What the explorer's ``k_d`` control sets for ``model``, as its label says it.

    For most models ``k_d × colour`` is the diffuse albedo: of the Lambert part the explorer adds, or of
    the model's own diffuse colour (:func:`diffuse_parameter`).  A model that reflects diffusely by
    itself without such a colour (a BRDF file: its colours are its own parameters) gets no Lambert part,
    so there the control sets only the ambient coefficient ``k_a``.

    Parameters
    ----------
    model : str
        A model or variant name.

    Returns
    -------
    str
        ``"k_d (diffuse albedo)"`` or ``"k_a (ambient)"``.

    Examples
    --------
    >>> kd_label("blinn-phong"), kd_label("oren-nayar")
    ('k_d (diffuse albedo)', 'k_d (diffuse albedo)')
    """
    cls, _ = _entry(model)
    if carries_diffuse(cls) and diffuse_parameter(cls) is None:
        return "k_a (ambient)"
    return "k_d (diffuse albedo)"


def diffuse_parameter(cls) -> str | None:
    """The colour parameter the explorer's ``k_d × colour`` fills: a diffuse model's first colour row.

    Parameters
    ----------
    cls : type
        A model class.

    Returns
    -------
    str or None
        ``"kd"`` (Lambert, Oren–Nayar), ``"base_color"`` (Disney), ``"rd"`` (Ashikhmin–Shirley); ``None``
        for a model that does not carry its own diffuse (the explorer adds ``Lambert(k_d × colour)``) and
        for a model read from a BRDF file (:func:`lighting.files.file_model`: every colour of its block
        is a control of its own; ``k_d × colour`` is then only the ambient coefficient).
    """
    if not carries_diffuse(cls) or getattr(cls, "file_path", None):
        return None  # a BRDF file's colours are its own parameters (its file says what they mean)
    return next((p.name for p in cls.parameters if p.kind == "color"), None)


def parameter_table(model: str) -> dict:
    """A model's (or variant's) parameter table by name.

    Parameters
    ----------
    model : str
        A name of :func:`lighting.models.model_variants`.

    Returns
    -------
    dict of str to Parameter
    """
    cls, _ = _entry(model)
    return {p.name: p for p in cls.parameters}


def offered_parameters(model: str) -> tuple:
    """The rows of a model's table the explorer offers as controls, in the table's order.

    Parameters
    ----------
    model : str
        A model or variant name.

    Returns
    -------
    tuple of Parameter
        The table without the variant's fixed arguments and the diffuse colour (:func:`diffuse_parameter`).
    """
    cls, fixed = _entry(model)
    skip = set(fixed) | {diffuse_parameter(cls)}
    return tuple(p for p in cls.parameters if p.name not in skip)


def parameter_defaults(model: str) -> dict:
    """The offered parameters' starting values: the table's defaults (``None`` stays ``None``).

    Parameters
    ----------
    model : str
        A model or variant name.

    Returns
    -------
    dict
        Parameter name → default.
    """
    return {p.name: _plain(p.default) for p in offered_parameters(model)}


def _plain(value):
    if isinstance(value, np.ndarray):
        value = value.reshape(-1).tolist()
    if isinstance(value, (list, tuple)):
        return tuple(float(x) for x in value)
    if isinstance(value, (np.floating, np.integer)) and not isinstance(value, np.bool_):
        return float(value)
    return value


def validate_parameter(p, value):
    """``value`` checked for the parameter ``p`` (:meth:`lighting.models.protocol.Parameter.check`).

    Parameters
    ----------
    p : Parameter
        The table row.
    value
        The value given.

    Returns
    -------
    float, tuple of float, bool, str or None
        The value as the state keeps it (a colour: a float for grey, else a 3-tuple).
    """
    return p.check(value)


def slider_range(p) -> tuple[float, float]:
    """The positions a slider of a number or colour row spans: ``control_range``, in log10 for log rows.

    A range without an end gets one: ``[low, low + 1]`` (no row of the registered models needs it).  A log
    slider cannot reach 0: it starts at the range's low end if positive, else six decades below its top
    (``shininess`` 1 … 1e6, ``nu`` 0.01 … 1e4).

    Parameters
    ----------
    p : Parameter
        A ``float`` or ``color`` row.

    Returns
    -------
    (float, float)
        The slider's ends (log10 of the value's ends for a log row).
    """
    lo, hi = p.control_range
    if not math.isfinite(hi):
        hi = lo + 1.0
    if p.log:
        lo = lo if lo > 0 else hi * 1e-6
        return math.log10(lo), math.log10(hi)
    return float(lo), float(hi)


def none_label(p) -> str:
    """What ``None`` means for a row whose default is ``None``, from its description ("None: = α_x").

    Parameters
    ----------
    p : Parameter
        A row of a parameter table.

    Returns
    -------
    str
        The text after ``None:`` up to a comma (``"default"`` if the description says nothing).
    """
    text = p.description
    k = text.find("None:")
    meaning = text[k + 5 :].strip(" )") if k >= 0 else "default"
    return meaning.split(",")[0].strip() or "default"


def implied_parameters(table: Mapping, params: Mapping, given: Mapping) -> dict:
    """What a change of a model's Fresnel controls implies for the rows the same change does not set.

    The conductor rows of a model (:data:`lighting.models.fresnel.CONDUCTOR_PARAMETERS`: ``metal``, ``eta``
    and ``k`` beside its ``fresnel`` choice) hang together; a person picks one of them and expects the
    others to follow, not a refusal:

    * picking a named metal turns the Fresnel term to ``"conductor"`` and hands ``η`` and ``k`` to the
      metal (``None``);
    * picking another Fresnel term leaves the metal (``"none"``) and ``η``, ``k`` (``None``), which apply
      to the conductor only;
    * setting ``η`` or ``k`` of a conductor while a metal is named leaves the metal, keeping its index as
      the starting point: the other of the two takes the metal's value (per channel).

    A row the change sets itself is never touched, so a contradictory request (``metal="gold"`` with
    ``fresnel="schlick"``) is still refused by the model.

    Parameters
    ----------
    table : mapping
        The model's offered rows, name → :class:`~lighting.models.protocol.Parameter`.
    params : mapping
        The model's parameters with the change applied (validated).
    given : mapping
        The rows the change sets, name → validated value.

    Returns
    -------
    dict
        Row → implied value (empty for a model without the conductor rows, or when nothing follows).

    Examples
    --------
    >>> table = parameter_table("cook-torrance")
    >>> implied_parameters(table, {**parameter_defaults("cook-torrance"), "metal": "gold"}, {"metal": "gold"})
    {'fresnel': 'conductor'}
    >>> implied_parameters(table, {**parameter_defaults("cook-torrance"), "fresnel": "conductor", "metal": "gold",
    ...                            "eta": 0.5}, {"eta": 0.5})["k"]   # gold's k, per channel
    (3.403381733021077, 2.2308700361010834, 1.869292682926829)
    """
    if not {"fresnel", "metal", "eta", "k"} <= set(table):
        return {}
    out = {}
    metal = params.get("metal", "none")
    if "metal" in given and metal != "none":
        out = {"fresnel": "conductor", "eta": None, "k": None}
    elif "fresnel" in given and params.get("fresnel") != "conductor":
        out = {"metal": "none", "eta": None, "k": None}
    elif metal != "none" and any(given.get(name) is not None for name in ("eta", "k")):
        from lighting.models.fresnel import metal_index

        eta, k = metal_index(metal)
        out = {"metal": "none", "eta": tuple(float(x) for x in eta), "k": tuple(float(x) for x in k)}
    return {name: value for name, value in out.items() if name not in given and params.get(name) != value}


def conductor_none_value(name: str, params: Mapping, *, whole: bool = False):
    """The index a conductor row set to ``None`` stands for: the named metal's, else ``η`` of ``F0`` and ``k = 0``.

    A slider shows one number, so an RGB index shows its largest channel (as an RGB value from a scene file does);
    ``whole=True`` gives the index itself, an RGB tuple where it differs per channel (what a released lock sets, so
    that the material looks the same after the release).

    Parameters
    ----------
    name : str
        ``"eta"`` or ``"k"`` (any other row: None).
    params : mapping
        The model's parameters (``metal`` and ``f0`` are read).
    whole : bool
        The whole index instead of its largest channel.

    Returns
    -------
    float, tuple of float or None

    Examples
    --------
    >>> round(conductor_none_value("eta", {"metal": "none", "f0": 0.04}), 6)
    1.5
    >>> round(conductor_none_value("k", {"metal": "gold", "f0": 0.04}), 3)
    3.403
    >>> [round(x, 3) for x in conductor_none_value("k", {"metal": "gold"}, whole=True)]
    [3.403, 2.231, 1.869]
    """
    if name not in ("eta", "k"):
        return None
    from lighting.models.fresnel import eta_from_f0, metal_index

    metal = params.get("metal", "none")
    if metal not in (None, "none"):
        value = metal_index(metal)[0 if name == "eta" else 1]
    elif name == "k":
        value = np.zeros(1)
    else:
        value = np.atleast_1d(eta_from_f0(params.get("f0", 0.04)))
    if not whole or np.all(value == value.flat[0]):
        return float(np.max(value))
    return tuple(float(x) for x in value)
