"""`to_pyvista` and `show`: the pipeline's results as pyvista meshes, checked off-screen."""

from __future__ import annotations

import numpy as np
import pytest
import pyvista as pv

from origami_cad.errors import PatternError
from origami_cad.fabrication import FabricationParams, fabricate
from origami_cad.fabrication.assembly import MATERIAL_COLORS
from origami_cad.kinematics.folding import fold_sequence
from origami_cad.pattern.design import load_pattern_source, miura_design
from origami_cad.strings import load_route
from origami_cad.viz.gltf import CREASE_COLORS, PANEL_COLOR
from origami_cad.viz.pyvista_mesh import STRING_COLOR, display_mode, show, to_pyvista


def _hex(mesh) -> str:
    return "#" + "".join(f"{int(c):02X}" for c in mesh.field_data["color"])


@pytest.fixture(scope="module")
def design():
    return miura_design(2, 3, 30.0, 30.0, 65.0)


def test_a_flat_pattern_is_its_panels_and_its_lines_by_kind(design):
    cp = design.pattern
    blocks = to_pyvista(design)
    assert blocks["panels"].n_cells == len(cp.faces)
    x0, y0, x1, y1 = cp.bounds
    np.testing.assert_allclose(blocks["panels"].bounds, [x0, x1, y0, y1, 0, 0], atol=1e-9)
    assert np.isclose(blocks["panels"].area, cp.face_areas().sum())
    for letter, name in {"M": "mountain", "V": "valley", "B": "border"}.items():
        lines = blocks[name]
        assert lines.n_cells == int((cp.assignments == letter).sum())
        total = lines.compute_cell_sizes(area=False, volume=False)["Length"].sum()
        assert np.isclose(total, cp.edge_lengths()[cp.assignments == letter].sum())
        assert _hex(lines) == CREASE_COLORS[letter]
        assert (lines.cell_data["color"] == lines.field_data["color"]).all()
    assert _hex(blocks["panels"]) == PANEL_COLOR and "cut" not in blocks.keys()


def test_a_folded_state_and_a_frame_of_coordinates_give_their_bounds(design):
    (state,) = fold_sequence(design, [0.6])
    for obj in (state, state.coords):  # a FoldedState, or a simulation frame (n, 3)
        panels = to_pyvista(obj, design)["panels"]
        lo, hi = state.coords.min(0), state.coords.max(0)
        np.testing.assert_allclose(panels.bounds, np.column_stack([lo, hi]).ravel(), atol=1e-9)
        assert np.isclose(panels.triangulate().area, design.pattern.face_areas().sum())
    with pytest.raises(ValueError, match=r"coords: expected \(12, 3\)"):
        to_pyvista(state.coords[:-1], design)
    # a state knows the pattern it folds; bare coordinates do not
    alone = to_pyvista(state)["panels"]
    np.testing.assert_allclose(alone.points, state.coords)
    with pytest.raises(PatternError, match="crease pattern"):
        to_pyvista(state.coords)


def test_the_printed_parts_are_coloured_by_material(small_miura_toml):
    fab = fabricate(load_pattern_source(small_miura_toml), FabricationParams(shell=0.5))
    blocks = to_pyvista(fab)
    assert blocks.keys() == ["infills", "midlayers", "shells", "creases"]
    volumes = fab.volumes()
    for name in blocks.keys():
        part = blocks[name]
        material = str(part.field_data["material"][0])
        assert material == ("PLA" if name in ("infills", "midlayers") else "TPU")
        assert _hex(part) == MATERIAL_COLORS[material]
        assert np.isclose(part.volume, volumes[name], rtol=1e-3)  # closed meshes


def test_a_route_draws_each_string_from_its_anchor(examples):
    design = load_pattern_source(examples / "miura_6x4.toml")
    spec = load_route(examples / "miura_route.toml", design.pattern)
    blocks = to_pyvista(spec, design)
    strings = [k for k in blocks.keys() if k.startswith("string")]
    assert len(strings) == len(spec.strings) == 4
    for name, route in zip(strings, spec.strings, strict=True):
        path = blocks[name]
        np.testing.assert_allclose(path.points[0], route.anchor)
        assert _hex(path) == STRING_COLOR
        assert path.n_points >= len(route.faces) + 1


def test_a_dcqc_result_shows_its_final_state_with_its_strings(examples):
    from origami_cad.strings import simulate_dcqc

    design = load_pattern_source(examples / "miura_6x4.toml")
    spec = load_route(examples / "miura_route.toml", design.pattern)
    result = simulate_dcqc(design, spec)
    last = to_pyvista(result, design)
    np.testing.assert_allclose(last["panels"].points, result.final_coords)
    for k, path in enumerate(result.final_strings):
        np.testing.assert_allclose(last[f"string {k}"].points, path)
    first = to_pyvista(result, design, frame=0)  # refolded at its fold ratio, no strings
    assert not [k for k in first.keys() if k.startswith("string")]
    assert np.isclose(first["panels"].triangulate().area, design.pattern.face_areas().sum())


def test_show_renders_off_screen_without_touching_pyvista_globals(tmp_path, design):
    (state,) = fold_sequence(design, [0.4])
    shot = tmp_path / "folded.png"
    image = show(state, design, mode="offscreen", window_size=(320, 240), screenshot=shot)
    assert image.shape == (240, 320, 3) and shot.is_file()
    assert not pv.OFF_SCREEN
    ink = np.any(image < 230, axis=-1).mean()
    assert 0.05 < ink < 0.9
    red = (image[..., 0] > 150) & (image[..., 1] < 90) & (image[..., 2] < 90)
    assert red.sum() > 20  # the mountain creases, in their colour


def test_the_display_mode_follows_the_environment(monkeypatch):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    monkeypatch.setattr("sys.platform", "linux")
    assert display_mode() == "offscreen"
    monkeypatch.setenv("DISPLAY", ":0")
    assert display_mode() == "window"
    with pytest.raises(ValueError, match="mode"):
        show(miura_design(2, 2, 20.0, 20.0, 60.0), mode="x")


def test_importing_the_viz_api_loads_neither_pyvista_nor_build123d():
    import subprocess
    import sys

    script = (
        "import sys, origami_cad.viz, origami_cad.viz.gltf\n"
        "from origami_cad.viz import show, to_pyvista\n"
        "print(sorted(m for m in ('pyvista', 'build123d', 'vtk') if m in sys.modules))"
    )
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"


def test_show_in_a_notebook_gives_pyvista_notebook_viewer(design):
    """Without trame, pyvista's notebook viewer is a static picture of the blocks."""
    import importlib.util

    if importlib.util.find_spec("trame") is not None:
        pytest.skip("trame is installed: the notebook viewer is a widget, not a picture")
    with pytest.warns(UserWarning, match="static image"):
        shown = show(design, mode="notebook", window_size=(200, 150))
    image = np.asarray(shown)[..., :3]
    assert image.shape == (150, 200, 3)
    assert 0.05 < np.any(image < 230, axis=-1).mean() < 0.9
    assert not pv.OFF_SCREEN


def test_parts_render_in_their_colours_with_one_legend_entry_per_label(tmp_path):
    import imageio.v3 as iio

    from origami_cad.viz.parts_render import render_parts

    stls = {}
    for k, centre in enumerate([(0, 0, 0), (3, 0, 0), (0, 3, 0)]):
        stls[f"module_{k}"] = tmp_path / f"module_{k}.stl"
        pv.Cube(center=centre).save(stls[f"module_{k}"])
    blue = "#1F77B4"
    colours = {name: blue for name in stls}

    def legend_rows(labels):
        out = render_parts(stls, tmp_path / "parts.png", labels=labels, colors=colours)
        image = iio.imread(out)[..., :3].astype(int)
        # the parts are blue (shaded: blue well above red)
        assert (image[..., 2] - image[..., 0] > 60).sum() > 0.01 * image[..., 0].size
        grey = np.flatnonzero((np.abs(image - 0xA0).max(axis=-1) <= 2).sum(axis=1) > 20)
        return grey.max() - grey.min() + 1  # the legend's grey box, pixel rows

    one = legend_rows({name: "modules" for name in stls})
    three = legend_rows(None)  # each part under its own name
    assert 10 < one and three > 2.5 * one
