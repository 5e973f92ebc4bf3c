"""Words in messages: a user's value shortened to one line, a count with its noun in the right number."""

from __future__ import annotations

import os

import numpy as np

__all__ = ["plural", "abbreviate", "quote", "quote_path", "MAX_VALUE_CHARS"]

#: Nouns whose plural is not the noun with ``s``.
_IRREGULAR = {"entry": "entries", "index": "indices", "vertex": "vertices", "process": "processes"}


def plural(count: int, noun: str, plural_form: str | None = None) -> str:
    """``count`` and ``noun``, the noun plural unless the count is one: ``"1 light"``, ``"2 lights"``, ``"0 lights"``.

    Parameters
    ----------
    count : int
        How many.
    noun : str
        The noun in the singular.
    plural_form : str, optional
        The plural, when it is not ``noun + "s"`` and not one of the few irregular nouns known here.

    Returns
    -------
    str
        ``f"{count} {noun}"`` in the right number.

    Examples
    --------
    >>> plural(1, "light"), plural(2, "light"), plural(0, "object"), plural(3, "entry")
    ('1 light', '2 lights', '0 objects', '3 entries')
    >>> plural(2, "dtype"), plural(1, "part"), plural(4, "datum", "data")
    ('2 dtypes', '1 part', '4 data')
    """
    if count == 1:
        return f"{count} {noun}"
    return f"{count} {plural_form or _IRREGULAR.get(noun, noun + 's')}"


#: Longest rendering of a user's value inside an error message.
MAX_VALUE_CHARS = 80


def abbreviate(text: str, limit: int = MAX_VALUE_CHARS, *, keep_end: bool = False) -> str:
    """``text`` cut to ``limit`` characters, with the number of characters left out.

    Parameters
    ----------
    text : str
        The text (any other value is converted with ``str``).
    limit : int, optional
        The longest text kept whole (default :data:`MAX_VALUE_CHARS`, 80).
    keep_end : bool, optional
        Keep the end instead of the start (a path: where it leads is at its end).

    Returns
    -------
    str
        ``text`` itself if it has at most ``limit`` characters; else its first ``max(limit // 2, 1)``
        characters followed by ``…(+N chars)``, ``N`` the number left out (with ``keep_end``, ``…(+N chars)``
        followed by the last ones).

    Examples
    --------
    >>> abbreviate("x" * 200, 20)
    'xxxxxxxxxx…(+190 chars)'
    >>> abbreviate("/" + "d" * 100 + "/file.png", 20, keep_end=True)
    '…(+100 chars)d/file.png'
    """
    text = str(text)
    if len(text) <= limit:
        return text
    keep = max(limit // 2, 1)
    if keep_end:
        return _end_of(text, keep)
    return f"{text[:keep]}…(+{len(text) - keep} chars)"


def _end_of(text: str, keep: int) -> str:
    """The last ``keep`` characters of ``text`` after ``…(+N chars)``, ``N`` the number left out."""
    return f"…(+{len(text) - keep} chars){text[-keep:]}"


def quote_path(path, limit: int = MAX_VALUE_CHARS) -> str:
    """A file path quoted for an error message: whole if short, else its end (the file's name and folders).

    Parameters
    ----------
    path : str or os.PathLike
    limit : int, optional
        The longest quoted path kept whole (default :data:`MAX_VALUE_CHARS`, 80).

    Returns
    -------
    str
        ``repr`` of the path, or its opening quote, ``…(+N chars)`` and the last ``limit // 2`` characters.

    Examples
    --------
    >>> quote_path("/" + "d" * 100 + "/mesh.obj", 20)
    "'…(+101 chars)/mesh.obj'"
    """
    text = repr(os.fspath(path))
    if len(text) <= limit:
        return text
    return text[0] + _end_of(text[1:], max(limit // 2, 1))  # the opening quote kept


def quote(value) -> str:
    """A short rendering of a user's value for an error message (never more than ``MAX_VALUE_CHARS``)."""
    try:
        if isinstance(value, (str, bytes)):
            return abbreviate(repr(value))
        arr = np.asarray(value)
        if arr.dtype.kind in "fiucb" and arr.ndim > 0:
            # One line whatever the shape: messages are one line.
            text = np.array2string(arr, separator=", ", threshold=8, edgeitems=2, max_line_width=10**6)
            text = " ".join(text.split())
        elif arr.dtype.kind in "fiucb":
            text = repr(arr.item())
        else:
            text = repr(value)
    except Exception:  # repr of exotic objects
        try:
            text = repr(value)
        except Exception:
            text = f"<{type(value).__name__}>"
    return abbreviate(text)
