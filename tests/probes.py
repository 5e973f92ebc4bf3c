"""Shared bookkeeping of the probes: one definition of "answered by a named error".

An illegal call is answered correctly when it raises ``ValueError`` or ``TypeError`` (a warning counts as
a failure: warnings are errors inside the call) whose message names the parameter and is one line of at
most :data:`MAX_MESSAGE` characters.  Everything else is counted by kind, with the first example of each.
"""

from __future__ import annotations

import warnings
from collections import Counter

MAX_MESSAGE = 400
FAILURE_KINDS = ("unnamed", "accepted", "other exception", "long message", "multi-line message")


class IllegalTally:
    """Calls with one illegal argument each, and how they were answered."""

    def __init__(self):
        self.counts = Counter()
        self.examples: dict[str, str] = {}

    @property
    def calls(self) -> int:
        return self.counts["calls"]

    @property
    def named(self) -> int:
        return self.counts["named"]

    def _fail(self, kind, example):
        self.counts[kind] += 1
        self.examples.setdefault(kind, example)

    def classify(self, label: str, param: str, call, *, names=None) -> None:
        """Run ``call`` (expected to refuse ``param``); ``names(message, param)`` overrides ``param in message``."""
        self.counts["calls"] += 1
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # a warning instead of an error is a failure too
            try:
                call()
            except (ValueError, TypeError) as exc:
                msg = str(exc)
                if not (names(msg, param) if names else param in msg):
                    self._fail("unnamed", f"{label}: {type(exc).__name__}: {msg}")
                    return
                self.counts["named"] += 1
                if len(msg) > MAX_MESSAGE:
                    self._fail("long message", f"{label}: {msg!r}")
                if "\n" in msg:
                    self._fail("multi-line message", f"{label}: {msg!r}")
                return
            except Exception as exc:  # noqa: BLE001 - counted by kind
                self._fail("other exception", f"{label}: {type(exc).__name__}: {exc}")
                return
        self._fail("accepted", label)

    def summary(self, name: str) -> str:
        share = 100.0 * self.named / self.calls if self.calls else 100.0
        kinds = ", ".join(f"{k} {self.counts[k]}" for k in FAILURE_KINDS)
        return f"probe {name} (illegal): {self.calls} calls, {self.named} named errors ({share:.0f} %); {kinds}"

    def failures(self) -> int:
        return sum(self.counts[k] for k in FAILURE_KINDS)
