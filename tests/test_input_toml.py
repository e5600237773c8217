"""Hostile and careless design, task and route files.

Each file is written here. Huge, non-finite or mistyped numbers and absurd counts
give a DesignError naming the file, the table and the key, on one line; nothing
is computed first.
"""

from __future__ import annotations

import pytest
from conftest import refused as refused_by

from origami_cad.design.task import load_task
from origami_cad.errors import DesignError, StringsError
from origami_cad.pattern import miura_pattern
from origami_cad.pattern.design import load_design
from origami_cad.strings.route import load_route

MIURA = """[pattern]
kind = "miura"
rows = {rows}
columns = {columns}
panel_length = {length}
panel_width = 30.0
sector_angle = 70.0
"""
TG = """[pattern]
kind = "transition-graph"
unit_width = {width}
copies = {copies}
entry_flag = 1
start = {start}
fold_ratio = 0.5
vectors = {vectors}
"""
TASK = """[arm]
start = {start}
points = {points}
alpha = 120.0
vectors = 6
length_range = {lengths}
samples = {samples}
[search]
runs = {runs}
seed = {seed}
"""
ROUTE = """[route]
max_turns = {turns}
[[route.strings]]
anchor = {anchor}
holes = {holes}
sides = {sides}
"""


def write(tmp_path, text, name="bad.toml"):
    p = tmp_path / name
    p.write_text(text)
    return p


def refused(load, path, *fragments):
    return refused_by(load, path, *fragments, error=DesignError)


def miura(**kw):
    return MIURA.format(**{"rows": 4, "columns": 6, "length": 20.0, **kw})


def tg(**kw):
    base = {"width": 36.0, "copies": 3, "start": "[0.0, 0.0]"}
    base["vectors"] = "[[40, 0], [30, 25], [30, -10]]"
    return TG.format(**{**base, **kw})


def test_the_base_files_load(tmp_path):
    assert load_design(write(tmp_path, miura(), "m.toml")).pattern.n_edges > 0
    assert load_design(write(tmp_path, tg(), "t.toml")).tg is not None


@pytest.mark.parametrize(
    "text, fragments",
    [
        (miura(rows=100_000, columns=100_000), ["key 'columns'", "panels, more than"]),
        (miura(rows=10**12), ["key 'rows'", "out of range"]),
        (miura(rows=10**30), ["key 'rows'", "too large"]),
        (miura(length="1e308"), ["key 'panel_length'", "too large"]),
        (miura(length="inf"), ["key 'panel_length'", "finite"]),
        (miura(length="nan"), ["key 'panel_length'", "finite"]),
        (miura(length="true"), ["key 'panel_length'", "expected a number"]),
        (tg(copies=100_000_000), ["key 'copies'", "out of range"]),
        (tg(copies=40_000), ["key 'copies'", "panels, more than"]),
        (tg(width="1e300"), ["key 'unit_width'", "too large"]),
        (tg(start="[nan, 0]"), ["key 'start'", "not a finite number"]),
        (tg(start="[1e300, 0]"), ["key 'start'", "not a finite number"]),
        (tg(vectors="[[40, 0], [inf, 25]]"), ["key 'vectors'", "item 1"]),
        (tg(vectors="[[40, 0], [30, nan]]"), ["key 'vectors'", "item 1"]),
        (tg(vectors="[[40, 0], [30, true]]"), ["key 'vectors'", "item 1"]),
        (tg(vectors='"40,0"'), ["key 'vectors'"]),
        ("[pattern]\nkind = " + "[" * 5000 + "]" * 5000, ["nested too deeply"]),
        ("[pattern]\nrows = " + "9" * 5000, ["not valid TOML"]),
    ],
)
def test_bad_design_files(tmp_path, text, fragments):
    refused(load_design, write(tmp_path, text), *fragments)


def task(**kw):
    base = {
        "start": "[0.0, 0.0]",
        "points": "[[250.0, 0.0], [50.0, 133.3]]",
        "lengths": "[10.0, 120.0]",
        "samples": 46,
        "runs": 2,
        "seed": 1,
    }
    return TASK.format(**{**base, **kw})


def test_the_base_task_loads(tmp_path):
    t, s = load_task(write(tmp_path, task(), "ok.toml"))
    assert t.points.shape == (2, 2) and s.seed == 1


@pytest.mark.parametrize(
    "kw, fragments",
    [
        ({"seed": -3}, ["key 'seed'", "out of range"]),
        ({"seed": 2**32}, ["key 'seed'", "out of range"]),
        ({"points": "[[nan, 0.0], [50.0, 133.3]]"}, ["key 'points'", "item 0"]),
        ({"points": "[[inf, 0.0], [50.0, 133.3]]"}, ["key 'points'", "item 0"]),
        ({"points": "[[1e300, 0.0], [50.0, 133.3]]"}, ["key 'points'", "item 0"]),
        ({"points": "[[true, 0.0], [50.0, 133.3]]"}, ["key 'points'", "item 0"]),
        ({"start": "[0.0, -inf]"}, ["key 'start'"]),
        ({"lengths": "[10.0, 1e400]"}, ["key 'length_range'"]),
        ({"samples": 10**9}, ["key 'samples'", "out of range"]),
        ({"runs": 10**9}, ["key 'runs'", "out of range"]),
        ({"runs": 0}, ["key 'runs'", "out of range"]),
    ],
)
def test_bad_task_files(tmp_path, kw, fragments):
    refused(load_task, write(tmp_path, task(**kw)), *fragments)


def test_task_areas_are_checked(tmp_path):
    text = task() + "[[arm.prohibited]]\ncircle = [0, 0, nan]\n"
    text = text.replace(
        "[search]", "[[arm.warning]]\npolygon = [[0, 0], [1, 0], [inf, 1]]\n[search]"
    )
    refused(load_task, write(tmp_path, text), "arm.warning", "key 'polygon'")
    text = task().replace("[search]", "[[arm.warning]]\ncircle = [0, 0, nan]\n[search]")
    refused(load_task, write(tmp_path, text), "key 'circle'")


@pytest.fixture(scope="module")
def cp():
    return miura_pattern(4, 6, 20.0, 30.0, 70.0)


def route(**kw):
    base = {
        "turns": 40,
        "anchor": "[10.0, 10.0, 20.0]",
        "holes": '["c0r0s0", "c0r0s1"]',
        "sides": '"auto"',
    }
    return ROUTE.format(**{**base, **kw})


def test_the_base_route_loads(tmp_path, cp):
    spec = load_route(write(tmp_path, route(), "ok.toml"), cp)
    assert len(spec.strings) == 1


@pytest.mark.parametrize(
    "kw, fragments",
    [
        ({"turns": "1e300"}, ["key 'max_turns'", "too large"]),
        ({"turns": "1e5"}, ["key 'max_turns'", "out of range"]),
        ({"turns": "nan"}, ["key 'max_turns'", "finite"]),
        ({"anchor": "[nan, 0, 20]"}, ["key 'anchor'", "item 0"]),
        ({"anchor": "[1e300, 0, 20]"}, ["key 'anchor'", "item 0"]),
        ({"holes": '["c0r0s0", [nan, 5]]'}, ["key 'holes'", "item 1", "finite [x, y]"]),
        ({"holes": '["c0r0s0", [1e300, 5]]'}, ["key 'holes'", "item 1"]),
        ({"holes": '["c0r0s0", [true, 5]]'}, ["key 'holes'", "item 1"]),
        ({"sides": "[{a = 1}, 2]"}, ["key 'sides'"]),
        ({"sides": "[[], []]"}, ["key 'sides'"]),
    ],
)
def test_bad_route_files(tmp_path, cp, kw, fragments):
    path = write(tmp_path, route(**kw))
    refused_by(lambda p: load_route(p, cp), path, *fragments, error=StringsError)


def test_huge_lists_of_unknown_keys_give_a_short_message(tmp_path):
    text = miura() + "".join(f"junk{k} = {k}\n" for k in range(5000))
    msg = refused(load_design, write(tmp_path, text), "unknown keys", "and 4995 more")
    assert len(msg) < 500


@pytest.mark.parametrize(
    "rel, fragment",
    [
        ("x\\u0000y.fold", "key 'path'"),
        ("n" * 400 + ".fold", "too long"),
        (".", "not a .fold"),
        ("sub.fold", "not a regular file"),
        ("missing.svg", "no such file"),
    ],
)
def test_design_paths_that_cannot_be_read(tmp_path, rel, fragment):
    (tmp_path / "sub.fold").mkdir()
    text = f'[pattern]\nkind = "file"\npath = "{rel}"\n'
    refused(load_design, write(tmp_path, text), "key 'path'", fragment)
