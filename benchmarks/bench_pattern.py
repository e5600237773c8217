"""Crease-pattern model: build and normalise a 100 x 100 Miura, round-trip FOLD and DXF."""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

from origami_cad.pattern import miura_pattern, read_pattern, write_pattern


def run() -> list[tuple[str, float, str]]:
    out = []
    t0 = time.perf_counter()
    cp = miura_pattern(100, 100, 10.0, 10.0, 60.0)
    t_build = time.perf_counter() - t0
    out.append((f"build + normalise 100 x 100 Miura ({cp.n_edges} edges), s", t_build, ""))
    t0 = time.perf_counter()
    problems = cp.check()
    out.append(("check() (Maekawa, Kawasaki, border), s", time.perf_counter() - t0, ""))
    assert not problems
    total = t_build
    with tempfile.TemporaryDirectory() as tmp:
        for ext in ("fold", "dxf"):
            path = Path(tmp) / f"m.{ext}"
            t0 = time.perf_counter()
            write_pattern(cp, path)
            t_w = time.perf_counter() - t0
            t0 = time.perf_counter()
            back = read_pattern(path)
            t_r = time.perf_counter() - t0
            assert back.same_graph(cp, tolerance=1e-9)
            out.append((f"{ext.upper()} write, s", t_w, ""))
            out.append((f"{ext.upper()} read (normalise + faces), s", t_r, ""))
            total += t_w + t_r
    out.append(("total: build + FOLD and DXF round trips, s", total, "target < 5 s"))
    return out
