"""Parts inside ``Locations``: one copy per location, in every mode, as build123d's own objects."""

from __future__ import annotations

import origami_cad.parts as P
import pytest
from build123d import Box, BuildPart, Locations, Mode, PolarLocations

PARTS = [P.DriverAdapter, P.Blocker, P.RingRail, P.TSAModule]
# far enough apart that no two copies touch, all inside the 2 m block below
SPOTS = [(-400, -400), (400, -400), (0, 400)]


@pytest.fixture(scope="module", params=PARTS, ids=lambda c: c.__name__)
def part(request):
    cls = request.param
    return cls, cls().volume


def test_every_location_gets_a_copy_with_its_labelled_tree(part):
    cls, volume = part
    with BuildPart() as bp:
        with Locations(*SPOTS):
            placed = cls()
    assert bp.part is not None
    assert bp.part.volume == pytest.approx(len(SPOTS) * volume, rel=1e-6)
    centres = sorted(round(s.center().X) for s in bp.part.solids() if abs(s.center().Y + 400) < 200)
    assert len(centres) >= 2 and centres[0] < 0 < centres[-1]
    # one labelled child tree per copy, each where its copy is
    labels = [c.label for c in placed.children]
    assert len(labels) % len(SPOTS) == 0 and len(set(labels)) == len(labels) // len(SPOTS)


def test_rotated_polar_copies(part):
    cls, volume = part
    with BuildPart() as bp:
        with PolarLocations(500, 4):
            cls(rotation=(0, 0, 30))
    assert bp.part.volume == pytest.approx(4 * volume, rel=1e-6)
    xs = [s.center().X for s in bp.part.solids()]
    assert max(xs) > 300 and min(xs) < -300


@pytest.mark.parametrize(
    ("mode", "expected"),
    [
        (Mode.ADD, lambda block, v: block + 2 * v),
        (Mode.SUBTRACT, lambda block, v: block - 2 * v),
        (Mode.INTERSECT, lambda block, v: 2 * v),
        (Mode.REPLACE, lambda block, v: 2 * v),
        (Mode.PRIVATE, lambda block, v: block),
    ],
    ids=lambda m: getattr(m, "name", ""),
)
def test_every_mode_combines_every_copy(part, mode, expected):
    cls, volume = part
    with BuildPart() as bp:
        # ADD beside the block, every other mode inside it
        block = Box(600, 600, 600) if mode == Mode.ADD else Box(2000, 2000, 800)
        block_volume = block.volume
        with Locations(*(SPOTS[:2] if mode != Mode.ADD else [(1000, 0), (-1000, 0)])):
            cls(mode=mode)
    assert bp.part.volume == pytest.approx(expected(block_volume, volume), rel=1e-6)
