"""Keep freed NumPy temporaries in the process instead of returning them to the OS.

glibc serves blocks above its ``mmap`` threshold (128 KiB at start, raised
dynamically up to a few MiB) straight from the kernel and unmaps them on free,
and trims the heap top above its trim threshold.  The image pipeline makes
dozens of 0.5–6 MiB temporaries per frame, so with the defaults every one of
them page-faults anew, frame after frame (``tests/explorer/test_bench.py``
counts the page faults; ``lighting-explorer bench`` times the frames).

:func:`tune_allocator` raises the thresholds (blocks up to 32 MiB come from the
heap, and up to 64 MiB of free heap is kept) for the front end's long-running
commands.  It is a process-wide setting, so the engine never calls it itself;
on systems without glibc it does nothing.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import sys

_M_TRIM_THRESHOLD, _M_TOP_PAD, _M_MMAP_THRESHOLD = -1, -2, -3
_done = False


def tune_allocator() -> bool:
    """Raise glibc's mmap and trim thresholds once (later calls only report).

    Returns
    -------
    bool
        True if the allocator accepted them; False elsewhere than Linux with glibc.
    """
    global _done
    if _done or not sys.platform.startswith("linux"):
        return _done
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
        mallopt = libc.mallopt
    except (OSError, AttributeError):
        return False
    ok = all(
        mallopt(param, value) == 1
        for param, value in ((_M_MMAP_THRESHOLD, 32 << 20), (_M_TRIM_THRESHOLD, 64 << 20), (_M_TOP_PAD, 16 << 20))
    )
    _done = ok
    return ok
