"""The whole chain on a few small corpus patterns, as a user runs it (``make test``'s part of
``make corpus``): check, fold, fabricate at 150 mm wide, plan-route with the TSA on a ring
and no string count, and simulate on the route it wrote, through ``origami_cad.cli.main``.

The patterns are the corpus entries marked ``fast`` in ``tests/data/corpus.toml``, from
different tools (Origami Simulator, FOLD's examples); ``make corpus`` runs all of them.
"""

from __future__ import annotations

import json
import math

import pytest
from corpus import DATA, MAX_STRAIN, RATIO, WIDTH, fold_measures, load_manifest

from origami_cad.cli import main

FAST = load_manifest(fast=True)


def test_the_fast_patterns_come_from_several_tools():
    assert 3 <= len(FAST) <= 4
    assert len({e["source"] for e in FAST}) >= 2


def _largest_turn(path) -> float:
    """The largest dihedral angle (deg) of a mountain or valley crease in a FOLD file's
    last frame."""
    doc = json.loads(path.read_text())
    frames = doc.get("file_frames") or [doc]
    coords = frames[-1].get("vertices_coords", doc["vertices_coords"])
    faces = doc["faces_vertices"]

    def normal(loop):
        p = [coords[v] + [0.0] * (3 - len(coords[v])) for v in loop]
        n = [0.0, 0.0, 0.0]
        for i in range(len(p)):
            a, b = p[i], p[(i + 1) % len(p)]
            n[0] += (a[1] - b[1]) * (a[2] + b[2])
            n[1] += (a[2] - b[2]) * (a[0] + b[0])
            n[2] += (a[0] - b[0]) * (a[1] + b[1])
        size = math.sqrt(sum(c * c for c in n)) or 1.0
        return [c / size for c in n]

    side: dict[tuple[int, int], list[int]] = {}
    for f, loop in enumerate(faces):
        for i, a in enumerate(loop):
            b = loop[(i + 1) % len(loop)]
            side.setdefault((min(a, b), max(a, b)), []).append(f)
    normals = [normal(loop) for loop in faces]
    best = 0.0
    for (a, b), kind in zip(doc["edges_vertices"], doc["edges_assignment"], strict=True):
        pair = side.get((min(a, b), max(a, b)), [])
        if kind in ("M", "V") and len(pair) == 2:
            dot = sum(p * q for p, q in zip(normals[pair[0]], normals[pair[1]], strict=True))
            best = max(best, math.degrees(math.acos(max(-1.0, min(1.0, dot)))))
    return best


@pytest.mark.parametrize("entry", FAST, ids=[e["file"] for e in FAST])
def test_the_whole_chain_runs_on_a_public_pattern(entry, tmp_path, capsys):
    src = str(DATA / entry["file"])
    size = ["--width", WIDTH]
    assert main(["check", src]) == 0

    assert main(["fold", src, *size, "--ratio", RATIO, "-o", str(tmp_path / "f.fold")]) == 0
    share, strain, creases = fold_measures(tmp_path / "f.fold")
    assert creases and share >= 0.5 and strain <= MAX_STRAIN

    assert main(["fabricate", src, *size, "-o", str(tmp_path / "fab")]) == 0
    made = {p.name: p.stat().st_size for p in (tmp_path / "fab").iterdir()}
    assert made.get("print.3mf", 0) > 0 and made.get("assembly.step", 0) > 0

    route = tmp_path / "route" / "route.toml"
    assert main(["plan-route", src, *size, "--tsa", "ring", "-o", str(route)]) == 0
    assert "the fewest that reach the target" in capsys.readouterr().out
    plan = json.loads((route.parent / "routes.json").read_text())
    assert plan["routes"] and plan["routes"][0]["strings"]

    # eight equal TSA steps keep it short (make corpus runs the default steps)
    sim = tmp_path / "sim"
    assert main(["simulate", src, str(route), *size, "--steps", "8", "-o", str(sim)]) == 0
    assert json.loads((sim / "simulation.json").read_text())
    # the strings fold the sheet: a crease turns by the last state
    assert _largest_turn(sim / "states.fold") > 1.0
