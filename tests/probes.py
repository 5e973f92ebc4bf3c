"""Shared bookkeeping of the probes: one definition of "answered by a named error".

An illegal call is answered correctly when it raises ``ValueError`` or ``TypeError`` (a warning counts as
a failure: warnings are errors inside the call) whose message names the parameter and is one line of at
most :data:`MAX_MESSAGE` characters.  Everything else is counted by kind, with the first example of each.
"""

from __future__ import annotations

import warnings
from collections import Counter

MAX_MESSAGE = 400

#: Hypothesis settings of the probes: the same examples on every run, no time limit per example.
PROBE_SETTINGS = dict(derandomize=True, deadline=None, database=None)
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


class LegalTally:
    """Legal (extreme) calls: every array they return must be finite, in range and of the asked dtype, with
    no warning.  Failures are counted by kind, with up to three examples of each."""

    def __init__(self):
        self.cases = 0
        self.failures = Counter()
        self.examples: dict[str, list[str]] = {}

    def fail(self, kind, what):
        self.failures[kind] += 1
        examples = self.examples.setdefault(kind, [])
        if len(examples) < 3:
            examples.append(what)

    def check(self, what, fn, *, dtype, lo=0.0, hi=None):
        """Run ``fn``; its arrays (one, a list or a dict of them) must be finite, in ``[lo, hi]``, of ``dtype``."""
        import numpy as np

        self.cases += 1
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                results = fn()
            except Exception as exc:  # noqa: BLE001 - counted, reported below
                self.fail("exception", f"{what}: {type(exc).__name__}: {exc}")
                return
        if caught:
            self.fail("warning", f"{what}: {caught[0].category.__name__}: {caught[0].message}")
        if isinstance(results, dict):
            results = list(results.values())
        for r in results if isinstance(results, list) else [results]:
            r = np.asarray(r)
            if r.dtype != dtype:
                self.fail("dtype", f"{what}: {r.dtype} for {np.dtype(dtype)}")
            if np.any(np.isnan(r)):
                self.fail("nan", what)
            elif np.any(np.isinf(r)):
                self.fail("inf", what)
            elif np.any(r < lo) or (hi is not None and np.any(r > hi)):
                self.fail("negative" if np.any(r < lo) else "above range", what)

    def summary(self):
        kinds = ", ".join(f"{k} {v}" for k, v in sorted(self.failures.items())) or "none"
        return f"{self.cases} cases, {sum(self.failures.values())} failures ({kinds})"
