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

__all__ = ["load_brdf", "reader_extensions"]

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
    if not isinstance(path, str | os.PathLike):
        raise TypeError(f"load_brdf: path must be a str or os.PathLike; got {type(path).__name__}")
    name = os.fspath(path)
    ext = os.path.splitext(name)[1].lower()
    if ext not in READERS:
        allowed = ", ".join(READERS)
        raise ValueError(f"load_brdf: {name!r} has no BRDF reader for {ext or '(no extension)'!r}; allowed: {allowed}")
    return importlib.import_module(READERS[ext]).load(name, **params)
