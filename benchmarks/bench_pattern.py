"""Crease-pattern model: build and normalise a 100 x 100 Miura, round-trip FOLD and DXF."""

from __future__ import annotations

import tempfile
from pathlib import Path

from clock import Clock, cpu_row

from origami_cad.pattern import miura_pattern, read_pattern, write_pattern


def run() -> list[tuple[str, float, str]]:
    out = []
    clock = Clock()
    cp = miura_pattern(100, 100, 10.0, 10.0, 60.0)
    t_build, c_build = clock.lap()
    out.append((f"build + normalise 100 x 100 Miura ({cp.n_edges} edges), wall s", t_build, ""))
    out.append(cpu_row(c_build))
    problems = cp.check()
    wall, cpu = clock.lap()
    out.append(("check() (Maekawa, Kawasaki, border), wall s", wall, ""))
    out.append(cpu_row(cpu))
    assert not problems
    total, total_cpu = t_build, c_build
    with tempfile.TemporaryDirectory() as tmp:
        for ext in ("fold", "dxf"):
            path = Path(tmp) / f"m.{ext}"
            clock.lap()
            write_pattern(cp, path)
            t_w, c_w = clock.lap()
            back = read_pattern(path)
            t_r, c_r = clock.lap()
            assert back.same_graph(cp, tolerance=1e-9)
            out.append((f"{ext.upper()} write, wall s", t_w, ""))
            out.append(cpu_row(c_w))
            out.append((f"{ext.upper()} read (normalise + faces), wall s", t_r, ""))
            out.append(cpu_row(c_r))
            total += t_w + t_r
            total_cpu += c_w + c_r
    out.append(("total: build + FOLD and DXF round trips, wall s", total, "target < 5 s"))
    out.append(cpu_row(total_cpu, "target < 5 s"))
    return out
