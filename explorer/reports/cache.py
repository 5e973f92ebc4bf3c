"""Saved accuracy studies: what ``report accuracy`` measured, kept for the figures to draw from.

A study of :mod:`lighting.validation.accuracy` takes seconds (quick) to many minutes (full); the
lecture-note figures that plot it (``accuracy_integration``, ..., ``accuracy_ibl``) read the points
``lighting-explorer report accuracy`` saved here instead of measuring again.

* **Where.**  The folder named by ``LIGHTING_EXPLORER_CACHE``, else ``$XDG_CACHE_HOME/lighting-explorer``,
  else ``~/.cache/lighting-explorer`` (:func:`cache_dir`).
* **Keyed.**  One file per study, settings and engine: the file name carries a digest of the engine's
  key (:func:`engine_key`: the package version and a digest of the ``lighting`` package's source
  files) and of the study's settings (:func:`lighting.validation.accuracy.study_settings`, quick or
  full), and the file repeats both; a result of another engine or other settings is never read.
* **Safe.**  Files are written atomically (:func:`explorer.output.atomic_write`).  A file that is
  corrupt, of another engine or settings, or not one of ours is ignored (the study is measured again),
  never an error; a folder that cannot be written is simply not written.

The cache lives here, beside the report that fills it, and not in the engine: it is a front end's
file in the user's home (environment variables, atomic writes of :mod:`explorer.output`), and the
engine keeps no state on disk.

Examples
--------
>>> import tempfile
>>> from lighting.validation.accuracy import run_studies
>>> folder = tempfile.mkdtemp()
>>> study = run_studies(quick=True, only="precision")[0]
>>> path = save_study(study, quick=True, by="lighting-explorer report accuracy", folder=folder)
>>> saved = load_study("precision", quick=True, folder=folder)
>>> repr(saved.study.points) == repr(study.points), saved.by, saved.quick  # every float to the bit
(True, 'lighting-explorer report accuracy', True)
>>> load_study("precision", quick=False, folder=folder) is None  # the full settings were never measured
True
"""

from __future__ import annotations

import functools
import hashlib
import json
import math
import os
from dataclasses import asdict, dataclass, fields

__all__ = ["CACHE_ENV", "CachedStudy", "cache_dir", "cache_path", "engine_key", "load_study", "save_study"]

#: The environment variable naming the cache folder.
CACHE_ENV = "LIGHTING_EXPLORER_CACHE"
#: What every cache file says it is (files without it are not ours).
FORMAT = "lighting-explorer accuracy study"
#: The layout of the file; another layout is read as a miss.
LAYOUT = 1


@dataclass(frozen=True)
class CachedStudy:
    """A study read from the cache, with where it came from."""

    #: The :class:`lighting.validation.accuracy.Study` as it was measured.
    study: object
    #: Measured with the quick settings (else the full ones).
    quick: bool
    #: The command that measured it, e.g. ``"lighting-explorer report accuracy"``.
    by: str
    #: The file it was read from.
    path: str


def cache_dir() -> str:
    """The cache folder (not created here).

    Returns
    -------
    str
        ``$LIGHTING_EXPLORER_CACHE`` if set and not empty, else ``$XDG_CACHE_HOME/lighting-explorer``
        (an absolute ``XDG_CACHE_HOME`` only, as the XDG specification asks), else
        ``~/.cache/lighting-explorer``.
    """
    own = os.environ.get(CACHE_ENV, "")
    if own:
        return os.path.abspath(os.path.expanduser(own))
    xdg = os.environ.get("XDG_CACHE_HOME", "")
    if xdg and os.path.isabs(xdg):
        return os.path.join(xdg, "lighting-explorer")
    return os.path.join(os.path.expanduser("~"), ".cache", "lighting-explorer")


@functools.lru_cache(maxsize=1)
def engine_key() -> dict:
    """The engine a result was measured with: the package version and a digest of its source.

    Returns
    -------
    dict
        ``{"version": lighting.__version__, "source_sha256": hex digest}`` over every ``.py`` file of
        the ``lighting`` package (relative path and bytes, in sorted order): an edited engine misses
        the cache even when its version number did not change.
    """
    import lighting

    root = os.path.dirname(os.path.abspath(lighting.__file__))
    files = []
    for folder, dirs, names in os.walk(root):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__")
        files += [os.path.join(folder, n) for n in names if n.endswith(".py")]
    h = hashlib.sha256()
    for path in sorted(files, key=lambda p: os.path.relpath(p, root).replace(os.sep, "/")):
        rel = os.path.relpath(path, root).replace(os.sep, "/")
        with open(path, "rb") as f:
            data = f.read()
        h.update(f"{rel}\0{len(data)}\0".encode())
        h.update(data)
    return {"version": lighting.__version__, "source_sha256": h.hexdigest()}


def _key(study: str, quick: bool) -> dict:
    from lighting.validation.accuracy import study_settings

    return {
        "study": study,
        "settings": "quick" if quick else "full",
        "parameters": study_settings(study, quick),
        "engine": engine_key(),
    }


def _digest(key: dict) -> str:
    return hashlib.sha256(json.dumps(key, sort_keys=True, ensure_ascii=True).encode()).hexdigest()


def cache_path(study: str, quick: bool, folder: str | None = None) -> str:
    """The file that holds ``study`` measured with these settings by this engine.

    Parameters
    ----------
    study : str
        A study of :data:`lighting.validation.accuracy.STUDY_NAMES`.
    quick : bool
        The quick settings (else the full ones).
    folder : str, optional
        The cache folder (default :func:`cache_dir`).

    Returns
    -------
    str
        ``FOLDER/accuracy-STUDY-quick|full-DIGEST.json``; the digest covers the settings and the engine.
    """
    name = f"accuracy-{study}-{'quick' if quick else 'full'}-{_digest(_key(study, quick))[:20]}.json"
    return os.path.join(folder or cache_dir(), name)


def save_study(study, *, quick: bool, by: str, folder: str | None = None) -> str | None:
    """Save a measured study (atomically); nothing happens when the folder cannot be written.

    Parameters
    ----------
    study : lighting.validation.accuracy.Study
        As :func:`lighting.validation.accuracy.run_studies` returned it, with the settings ``quick`` says.
    quick : bool
        Whether it was run with the quick settings.
    by : str
        The command that measured it (shown in the figures' captions).
    folder : str, optional
        The cache folder (default :func:`cache_dir`).

    Returns
    -------
    str or None
        The file written, or ``None`` when it could not be written.
    """
    from ..output import OutputError, atomic_write

    key = _key(study.name, quick)
    record = {
        "format": FORMAT,
        "layout": LAYOUT,
        "key": key,
        "by": str(by),
        "description": study.description,
        "points": [asdict(p) for p in study.points],
    }
    path = cache_path(study.name, quick, folder)
    try:
        os.makedirs(os.path.dirname(path), exist_ok=True)
        atomic_write(path, (json.dumps(record, ensure_ascii=False, indent=1) + "\n").encode("utf-8"), flag="cache")
    except (OSError, OutputError):
        return None  # a cache is a convenience: an unwritable folder only means measuring again next time
    return path


_POINT_TYPES = None


def _point(d):
    """A :class:`~lighting.validation.accuracy.Point` from its saved fields, or ``None`` for anything else."""
    global _POINT_TYPES
    from lighting.validation.accuracy import Point

    if _POINT_TYPES is None:
        kinds = {"str": (str,), "int": (int,), "float": (float,), "bool": (bool,)}
        _POINT_TYPES = {f.name: kinds[f.type] for f in fields(Point)}
    if not isinstance(d, dict) or set(d) != set(_POINT_TYPES):
        return None
    for name, kinds in _POINT_TYPES.items():
        value = d[name]
        if not isinstance(value, kinds) or (isinstance(value, bool) and bool not in kinds):
            return None
        if isinstance(value, float) and math.isinf(value):
            return None
    return Point(**d)


def load_study(study: str, *, quick: bool, folder: str | None = None) -> CachedStudy | None:
    """The saved study for this engine and these settings, or ``None`` (a miss).

    Parameters
    ----------
    study : str
        A study of :data:`lighting.validation.accuracy.STUDY_NAMES`.
    quick : bool
        The quick settings (else the full ones).
    folder : str, optional
        The cache folder (default :func:`cache_dir`).

    Returns
    -------
    CachedStudy or None
        ``None`` when there is no file, or it cannot be read, is not JSON, is not one of ours, was
        measured by another engine or with other settings, or holds a malformed point.
    """
    from lighting.validation.accuracy import Study

    path = cache_path(study, quick, folder)
    try:
        with open(path, encoding="utf-8") as f:
            record = json.load(f)
    except (OSError, ValueError):
        return None
    if not isinstance(record, dict) or record.get("format") != FORMAT or record.get("layout") != LAYOUT:
        return None
    if record.get("key") != _key(study, quick):
        return None
    by, description, raw = record.get("by"), record.get("description"), record.get("points")
    if not isinstance(by, str) or not isinstance(description, str) or not isinstance(raw, list) or not raw:
        return None
    points = [_point(d) for d in raw]
    if any(p is None or p.study != study for p in points):
        return None
    return CachedStudy(Study(study, description, points), quick, by, path)
