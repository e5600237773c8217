"""Run every benchmark (``make bench``) and print timings against their targets.

Each ``bench_*.py`` module defines ``run() -> list[tuple[str, float, str]]``:
(what, measured value, target text). Benchmarks are never part of the tests.
"""

from __future__ import annotations

import importlib
import os
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def main(names: list[str]) -> int:
    sys.path.insert(0, str(HERE))
    modules = sorted(p.stem for p in HERE.glob("bench_*.py"))
    if names:
        modules = [m for m in modules if any(n in m for n in names)]
    load = os.getloadavg()
    print(
        f"load average at the start (1, 5, 15 min): {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}"
        f" on {os.cpu_count()} CPUs: wall-clock figures need a quiet machine, CPU ones less so"
    )
    for name in modules:
        mod = importlib.import_module(name)
        print(f"== {name}: {mod.__doc__.strip().splitlines()[0]}")
        t0, c0 = time.perf_counter(), time.process_time()
        for what, value, target in mod.run():
            print(f"   {what:<58s} {value:>12.4g}   {target}")
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        print(f"   ({wall:.1f} s wall, {cpu:.1f} s CPU of this process)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
