"""BRDFs read from files: ``load_brdf(path, **params)`` chooses a reader by the file's extension.

=========== ====================================================================================
``.binary`` MERL measured isotropic BRDFs (:mod:`lighting.files.merl`)
``.brdf``   BRDF Explorer's analytic format: a parameter block and a GLSL ``BRDF(L, V, N, X, Y)``
            function, evaluated by the engine's own interpreter (:mod:`lighting.files.brdf_format`)
=========== ====================================================================================

A file is untrusted input: nothing in it runs as Python, its size and the memory it needs are
checked before anything is allocated, and a bad file gives one ``ValueError`` naming the file,
the place in it and what is allowed.  The model a reader returns is a BRDF like any built-in
one (``eval`` gives ``f_r`` in 1/sr, zero below the horizon).

Image files (PNG, Radiance ``.hdr``, PFM, ``.npy``, OpenEXR) are read and written, with the same
checks, by :mod:`lighting.files.images` (each format in a module of its own: ``png``, ``rgbe``, ``pfm``,
``npy``, ``exr``).

Examples
--------
>>> from lighting.files import load_brdf, reader_extensions
>>> reader_extensions()
('.binary', '.brdf')
>>> load_brdf("material.xyz")
Traceback (most recent call last):
...
ValueError: load_brdf: 'material.xyz' has no BRDF reader for '.xyz'; allowed: .binary, .brdf
"""

from __future__ import annotations

import importlib
import os
import re

__all__ = ["load_brdf", "file_model", "reader_extensions"]

#: Extension → the module whose ``load(path, **params)`` reads it (imported when first used).
READERS = {".binary": "lighting.files.merl", ".brdf": "lighting.files.brdf_format"}


def reader_extensions() -> tuple[str, ...]:
    """The file extensions :func:`load_brdf` reads.

    Returns
    -------
    tuple of str
        Lower-case extensions with their dot, e.g. ``(".binary", ".brdf")``.
    """
    return tuple(READERS)


def load_brdf(path, **params):
    """A BRDF from a file, chosen by its extension.

    Parameters
    ----------
    path : str or os.PathLike
        The file (``.binary``: MERL measured data; ``.brdf``: BRDF Explorer's analytic format).
    **params
        Values of the file's parameters by name (``.brdf`` parameter blocks), or reader options.

    Returns
    -------
    lighting.models.base.BRDF
        The model the file describes.

    Raises
    ------
    ValueError
        An extension without a reader, or a file the reader refuses (the message names the file).
    """
    name, reader = _reader("load_brdf", path)
    return reader.load(name, **params)


def _reader(caller: str, path):
    """The file name and the reader module for ``path`` (by extension), or a named error."""
    if not isinstance(path, str | os.PathLike):
        raise TypeError(f"{caller}: path must be a str or os.PathLike; got {type(path).__name__}")
    name = os.fspath(path)
    ext = os.path.splitext(name)[1].lower()
    if ext not in READERS:
        allowed = ", ".join(READERS)
        raise ValueError(f"{caller}: {name!r} has no BRDF reader for {ext or '(no extension)'!r}; allowed: {allowed}")
    return name, importlib.import_module(READERS[ext])


class _FromFile:
    """What every file model class adds: the file it came from, and that file in its scene-file form."""

    #: The file's absolute path.
    file_path: str = ""

    def to_dict(self) -> dict:
        """The model as a scene file's part table: ``{"file": path, parameter: value, ...}``.

        Returns
        -------
        dict
        """
        d = super().to_dict()
        d.pop("model")
        return {"file": self.file_path, **d}


def _model_name(path: str, registry: dict) -> str:
    """The file's stem as a model name (lower case, ``-`` between words), unique in ``registry``.

    A name held by another model gets ``-2``, ``-3``, …; one held by a model of the same file is reused.
    """
    stem = re.sub(r"[^a-z0-9]+", "-", os.path.splitext(os.path.basename(path))[0].lower()).strip("-") or "brdf-file"
    name, k = stem, 1
    while name in registry and getattr(registry[name], "file_path", None) != path:
        k += 1
        name = f"{stem}-{k}"
    return name


def file_model(path, name: str | None = None, *, register: bool = False) -> type:
    """A model class from a file: its parameter table is the file's, and its instances share what was read.

    Where :func:`load_brdf` gives one model, this gives its class, for the places that build models by
    name from a parameter table: scene files (``parts = [{file = "paint.brdf", roughness = 0.2}]``)
    and the explorer (``lighting-explorer --brdf FILE``), whose controls are generated from the table.

    Parameters
    ----------
    path : str or os.PathLike
        A file :func:`load_brdf` reads (``.binary``, ``.brdf``).
    name : str, optional
        The model's name; default the file's stem in lower case with ``-`` between words, made unique
        among the registered models (``-2``, ``-3``, … when another model has it).
    register : bool
        Register the class (:func:`lighting.models.register_model`) so the explorer's model list and
        scene files' ``model = NAME`` find it; registering a file again replaces its earlier class.

    Returns
    -------
    type
        A BRDF class: ``cls(**values)`` takes the file's parameters (a ``.brdf`` file's block; for
        MERL data, ``interpolation``), ``cls.parameters`` is their table, ``cls.file_path`` the
        absolute path, and ``to_dict()`` gives ``{"file": path, ...}``.

    Raises
    ------
    ValueError
        An extension without a reader, or a bad file (the reader's one-line message).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (d / "Flat Grey.brdf").write_text(
    ...     "::begin parameters\\nfloat albedo 0 1 0.5\\n::end parameters\\n::begin shader\\n"
    ...     "vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) { return vec3(albedo / 3.14159265358979); }\\n"
    ...     "::end shader\\n")
    >>> Grey = file_model(d / "Flat Grey.brdf")
    >>> Grey.name, [p.name for p in Grey.parameters]
    ('flat-grey', ['albedo'])
    >>> round(float(Grey(albedo=0.8).eval((0, 0, 1.0), (0, 0, 1.0), (0, 0, 1.0))[0]), 4)
    0.2546
    """
    from ..models import protocol

    filename, reader = _reader("file_model", path)
    absolute = os.path.abspath(filename)
    base = reader.model_class(filename)
    if name is None:
        name = _model_name(absolute, protocol._REGISTRY)
    elif not isinstance(name, str) or not re.fullmatch(r"[a-z0-9][a-z0-9_-]*", name):
        raise ValueError(f"file_model: name must be lower-case letters, digits, '-' or '_'; got {name!r}")
    cls = type(base.__name__, (_FromFile, base), {"name": name, "file_path": absolute, "__doc__": base.__doc__})
    if register:
        protocol.register_model(cls, name, replace=getattr(protocol._REGISTRY.get(name), "file_path", None) == absolute)
    return cls
