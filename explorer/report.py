"""``lighting-explorer report accuracy|stability``: the two accuracy reports."""

from __future__ import annotations

import importlib
import sys

REPORTS = {
    "accuracy": ("explorer.report_accuracy", "error against run time wherever the engine trades accuracy for speed"),
    "stability": ("explorer.report_stability", "numerical stability on stiff and extreme cases, against mpmath"),
}


def main(argv=None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if not argv or argv[0] in ("-h", "--help") or argv[0] not in REPORTS:
        lines = ["usage: lighting-explorer report {accuracy,stability} [--quick] [--out DIR] ...", ""]
        lines += [f"  {name:10s} {text}" for name, (_, text) in REPORTS.items()]
        if argv and argv[0] not in ("-h", "--help"):
            from lighting._numeric import _fmt

            print(f"lighting-explorer: error: unknown report {_fmt(argv[0])}; choose accuracy or stability",
                  file=sys.stderr)  # fmt: skip
            return 2
        print("\n".join(lines))
        return 0
    return importlib.import_module(REPORTS[argv[0]][0]).main(argv[1:])


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
