"""The parametric crawler (``origami_cad.crawler.design``) and the joint design and gait
search (``origami_cad.crawler.design_search``, ``design-gait --design``).

The search here is tiny (one friction, two candidates, two steps between keyframes): it
checks that the designed crawler's written files walk the scored stride, not how far it
walks (docs/crawler.md, "Designing the crawler").
"""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest
from conftest import CRAWLER, CRAWLER_FILES, make_crawler_script

from origami_cad.cli import main
from origami_cad.crawler.design import (
    ENVELOPE,
    CrawlerDesign,
    check_envelope,
    crawler_extent,
    crawler_files,
    crawler_pattern,
    module_centre,
    write_crawler,
)
from origami_cad.crawler.design_search import (
    DESIGN_GENES,
    decode_design,
    design_crawler,
    max_extent,
    parse_design_bounds,
)
from origami_cad.crawler.gait import GaitSettings
from origami_cad.crawler.robot import load_robot
from origami_cad.crawler.walk import robot_params
from origami_cad.errors import DesignError


def test_the_generator_with_the_default_numbers_writes_the_committed_example(tmp_path):
    write_crawler(crawler_files(envelope=None), tmp_path)
    for name in CRAWLER_FILES:
        assert (tmp_path / name).read_bytes() == (CRAWLER / name).read_bytes(), name


def test_the_designed_crawler_is_the_generators_and_within_the_envelope(tmp_path):
    gen, designed = make_crawler_script(), CRAWLER.parent / "crawler_designed"
    files = crawler_files(gen.DESIGNED, gen.GAIT, header=gen.HEADER)  # checks it
    write_crawler(files, tmp_path)
    for name in CRAWLER_FILES:
        assert (tmp_path / name).read_bytes() == (designed / name).read_bytes(), name
    assert sorted(p.name for p in designed.iterdir()) == sorted(CRAWLER_FILES)  # one gait, no other
    extent = check_envelope(gen.DESIGNED)
    assert all(e <= limit for e, limit in zip(extent, ENVELOPE, strict=True))
    robot = load_robot(designed / "crawler.toml")
    sheet = robot.sheet(holes="auto")  # what the robot command prints: eq. 6's checks pass
    assert (sheet.thickness, sheet.shell) == (0.9, 0.5) and sheet.holes == "auto"
    assert sheet.half_height - sheet.shell >= 0.1 - 1e-9  # one layer of infill is left
    assert robot.gait_p.max() <= robot.blocker_angle / 180.0


@pytest.mark.parametrize("body", [180.0, 130.0])
def test_modules_are_centred_where_the_parts_library_centres_them(body):
    import shapely

    from origami_cad.fabrication import plan_panels

    cp = crawler_pattern(CrawlerDesign(body_length=body, leg_length=105.0))
    for label in ("leg_fl", "leg_rr"):
        outline = plan_panels(cp).outline(label)
        foot = shapely.Polygon(outline.outer).buffer(-1.0, join_style="mitre")
        assert module_centre(cp, label) == pytest.approx((foot.centroid.x, foot.centroid.y))


def test_the_envelope_refuses_the_built_robot_by_name_and_passes_a_shorter_body():
    with pytest.raises(DesignError) as err:
        crawler_files(CrawlerDesign())  # 349.9 mm long at its 20 deg rest
    message = str(err.value)
    assert "\n" not in message and "length (x)" in message and "340 mm" in message
    assert "20 deg" in message
    short = CrawlerDesign(body_length=140.0, leg_length=100.0)
    extent = check_envelope(short)
    assert all(e <= limit for e, limit in zip(extent, ENVELOPE, strict=True))
    # the rigid fold: longer at the rest than at the blocker, taller at the blocker
    rest, top = crawler_extent(short, 20.0), crawler_extent(short, 60.0)
    assert rest[0] > top[0] and top[2] > rest[2]
    assert rest[0] >= short.body_length + 2 * short.leg_length * np.cos(np.radians(20.0))
    with pytest.raises(DesignError, match="height"):
        check_envelope(short, envelope=(400.0, 400.0, 50.0))


def test_the_crease_layer_reaches_the_routes_and_the_simulation(tmp_path):
    stiff = CrawlerDesign(body_length=140.0, leg_length=100.0, crease_thickness=0.7, shell=0.6)
    robot = load_robot(write_crawler(crawler_files(stiff), tmp_path))
    params = robot_params(robot, friction=0.8)
    assert params.crease_thickness == 0.7 and params.friction == 0.8
    assert (
        params.crease_stiffness
        > 5 * robot_params(load_robot(CRAWLER / "crawler.toml")).crease_stiffness
    )
    with pytest.raises(DesignError, match="shell"):
        CrawlerDesign(crease_thickness=0.7, shell=0.8)  # s < (h - t) / 2 = 0.75


@pytest.mark.parametrize(
    "spec, word",
    [
        ("leg_length=130:90", "must not exceed"),
        ("blocker_angle=50:70", "outside"),
        ("foot=1:2", "unknown gene"),
        ("leg_length=90", "name=low:high"),
        ("crease_thickness=a:b", "not two numbers"),
    ],
)
def test_bad_design_bounds_are_refused_in_one_line(tmp_path, capsys, spec, word):
    with pytest.raises(DesignError, match=word):
        parse_design_bounds(spec)
    out = tmp_path / "out"
    rc = main(["design-gait", str(CRAWLER / "crawler.toml"), "-o", str(out), "--design", spec])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and word in err[0], err
    assert not out.exists()


def test_every_decoded_design_is_within_the_envelope_and_its_bounds():
    bounds = parse_design_bounds("leg_length=95:125,blocker_angle=50:60")
    rng = np.random.default_rng(3)
    for u in [np.zeros(5), np.ones(5), *rng.uniform(0, 1, (3, 5))]:
        d = decode_design(bounds, u)
        assert all(e <= limit + 1e-6 for e, limit in zip(max_extent(d), ENVELOPE, strict=True))
        for name in DESIGN_GENES[:1] + DESIGN_GENES[3:4]:
            low, high = bounds[name]
            assert low - 1e-9 <= getattr(d, name) <= high + 1e-9
        assert d.shell <= (2.2 - d.crease_thickness) / 2 - 0.1 + 1e-9  # one infill layer
    # legs that leave no body within the 340 mm are refused by name, not drawn
    with pytest.raises(DesignError, match="body of"):
        decode_design(parse_design_bounds("leg_length=150:160"), np.zeros(5))


def test_a_tiny_joint_search_writes_a_crawler_that_walks_the_scored_stride(tmp_path):
    start = load_robot(CRAWLER / "crawler.toml")
    settings = GaitSettings(frictions=(0.6,), popsize=2, generations=1, steps=2)
    search = design_crawler(start, settings, {"leg_length": (100.0, 110.0)})
    assert len(search.designs) == len(search.gait.candidates) == 3
    best = search.best_design
    assert 100.0 <= best.leg_length <= 110.0 and best.body_length < 180.0
    written = write_crawler(search.files(), tmp_path / "robot")
    robot = load_robot(written)
    out = tmp_path / "crawl"
    args = ["--steps", "2", "--cycles", "1", "--friction", "0.6"]
    assert main(["crawl", str(written), "-o", str(out), *args]) == 0
    forward = json.loads((out / "crawl.json").read_text())["displacement_total_mm"]
    assert forward == pytest.approx(search.gait.best.terms[0].forward, abs=1e-6)
    assert np.allclose(robot.gait_p, search.gait.best.ratios)
    info = search.to_dict()
    assert info["best_design"]["leg_length_mm"] == best.leg_length
    assert dataclasses.replace(best) == best
