"""The engine's bounded caches: the last few values made, by key, the one used longest ago dropped first.

Tables made once per model part or environment (albedo tables, filtered-sample tables, prefiltered levels, dominant
lights) are kept in one of these, so that memory stays bounded however many models or skies a session meets.  The
shading threads may share one: every operation holds its lock.
"""

from __future__ import annotations

import threading
from collections import OrderedDict

__all__ = ["Recent"]


class Recent:
    """The last ``size`` values by key; reading a value counts as using it.

    Parameters
    ----------
    size : int
        Values kept.

    Examples
    --------
    >>> kept = Recent(2)
    >>> kept.put("a", 1), kept.put("b", 2), kept.get("a"), kept.put("c", 3)
    (1, 2, 1, 3)
    >>> kept.get("b") is None, kept.get("a"), len(kept)  # "b" was used longest ago
    (True, 1, 2)
    """

    def __init__(self, size: int):
        self._size = size
        self._values: OrderedDict = OrderedDict()
        self._lock = threading.Lock()

    def get(self, key):
        """The value kept for ``key`` (now the most recently used), or None."""
        with self._lock:
            value = self._values.get(key)
            if value is not None:
                self._values.move_to_end(key)
            return value

    def put(self, key, value):
        """Keep ``value`` for ``key``, dropping the values used longest ago beyond ``size``; returns ``value``."""
        with self._lock:
            self._values[key] = value
            self._values.move_to_end(key)
            while len(self._values) > self._size:
                self._values.popitem(last=False)
        return value

    def clear(self) -> None:
        """Forget every value."""
        with self._lock:
            self._values.clear()

    def __len__(self) -> int:
        return len(self._values)
