"""Run every benchmark (``make bench``) and print timings against their targets.

Each ``bench_*.py`` module defines ``run() -> list[tuple[str, float, str]]``:
(what, measured value, target text). Benchmarks are never part of the tests.
"""

from __future__ import annotations

import importlib
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def main(names: list[str]) -> int:
    sys.path.insert(0, str(HERE))
    modules = sorted(p.stem for p in HERE.glob("bench_*.py"))
    if names:
        modules = [m for m in modules if any(n in m for n in names)]
    for name in modules:
        mod = importlib.import_module(name)
        print(f"== {name}: {mod.__doc__.strip().splitlines()[0]}")
        t0 = time.perf_counter()
        for what, value, target in mod.run():
            print(f"   {what:<58s} {value:>12.4g}   {target}")
        print(f"   ({time.perf_counter() - t0:.1f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
