"""STEP opened in FreeCAD itself (when installed): every solid in its part's colour.

FreeCAD 0.20's GUI importer (``ImportGui.insert``) runs off-screen
(``QT_QPA_PLATFORM=offscreen``) with its own throw-away settings folder. It is run with
STEP compound merging off (Preferences > Import-Export > STEP: "Enable STEP compound
merge" unchecked), the mode that keeps the assembly tree: each solid becomes a
feature, each part a compound. Skipped when ``freecadcmd`` is not installed
(``apt install freecad``).
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess

import pytest

from origami_cad.fabrication import FabricationParams, fabricate
from origami_cad.fabrication.assembly import MATERIAL_COLORS
from origami_cad.fabrication.exports.step import export_step_assembly
from origami_cad.fabrication.solids import PART_MATERIALS, PART_NAMES
from origami_cad.pattern.design import miura_design

FREECAD = shutil.which("freecadcmd") or shutil.which("FreeCADCmd")

SCRIPT = """
import json, FreeCAD, FreeCADGui
FreeCAD.ParamGet("User parameter:BaseApp/Preferences/Mod/Import/hSTEP").SetBool(
    "ReadShapeCompoundMode", False)
FreeCADGui.showMainWindow()
import ImportGui
doc = FreeCAD.newDocument()
ImportGui.insert({path!r}, doc.Name)
FreeCADGui.updateGui()
rows = []
for o in doc.Objects:
    vo = o.ViewObject
    colour = getattr(vo, "ShapeColor", None)
    solids = len(o.Shape.Solids) if hasattr(o, "Shape") else 0
    rows.append([o.Label, o.TypeId, solids, list(colour[:3]) if colour else None])
with open({out!r}, "w") as fh:
    json.dump(rows, fh)
"""


def _rgb(hexa: str) -> list[float]:
    h = hexa.lstrip("#")
    return [int(h[i : i + 2], 16) / 255 for i in (0, 2, 4)]


def _freecad(tmp_path, probe: str, step):
    """Run a probe script (``{path}``: the STEP, ``{out}``: its JSON) in FreeCAD; its rows."""
    out = tmp_path / "objects.json"
    script = tmp_path / "probe.py"
    script.write_text(probe.format(path=str(step), out=str(out)))
    home = tmp_path / "home"
    home.mkdir(exist_ok=True)
    env = {
        **os.environ,
        "QT_QPA_PLATFORM": "offscreen",
        "HOME": str(home),
        "XDG_CONFIG_HOME": str(home / ".config"),
        "XDG_DATA_HOME": str(home / ".local" / "share"),
    }
    run = subprocess.run(
        [FREECAD, str(script)], env=env, capture_output=True, text=True, timeout=600, check=False
    )
    assert out.is_file(), run.stdout[-2000:] + run.stderr[-2000:]
    return json.loads(out.read_text())


@pytest.mark.skipif(FREECAD is None, reason="FreeCAD is not installed (apt install freecad)")
def test_freecad_shows_every_solid_in_its_part_colour(tmp_path):
    fab = fabricate(miura_design(2, 3, 30.0, 30.0, 65.0), FabricationParams(shell=0.5))
    step = export_step_assembly(fab.parts, tmp_path / "assembly.step")
    rows = _freecad(tmp_path, SCRIPT, step)
    for name in PART_NAMES:
        expected = _rgb(MATERIAL_COLORS[PART_MATERIALS[name]])
        compounds = [r for r in rows if r[1] == "Part::Compound2" and r[0].startswith(name)]
        assert compounds, name
        for label, _, _, colour in compounds:  # the part itself, not grey
            assert colour == pytest.approx(expected, abs=2e-3), label
    modes = _freecad(tmp_path, SOLIDS_SCRIPT, step)
    assert set(modes) == {"merge", "no merge"}
    for mode, solids in modes.items():
        assert len(solids) == sum(len(v) for v in fab.parts.solids.values()), mode
        check_freecad_solids(solids, fab.parts)


def _both_merge_modes(per_object: str) -> str:
    """A FreeCAD probe script (``{path}``, ``{out}`` as :func:`_freecad` fills them) that
    imports the STEP with compound merge off (the assembly as link groups) and on (with
    App::Part groups), and writes, by mode, the rows ``per_object`` (the body of a loop over
    the document's objects ``o``, indented 8 spaces) appends to ``out``."""
    return (
        """
import json, FreeCAD, FreeCADGui, Part
FreeCADGui.showMainWindow()
import ImportGui
rows = {{}}
for merge in (False, True):
    FreeCAD.ParamGet("User parameter:BaseApp/Preferences/Mod/Import/hSTEP").SetBool(
        "ReadShapeCompoundMode", merge)
    doc = FreeCAD.newDocument()
    ImportGui.insert({path!r}, doc.Name, merge=merge, useLinkGroup=not merge)
    FreeCADGui.updateGui()
    out = []
    for o in doc.Objects:
"""
        + per_object
        + """    rows["merge" if merge else "no merge"] = out
with open({out!r}, "w") as fh:
    json.dump(rows, fh)
"""
    )


#: Per mode, each Part::Feature: label, solids, all valid, colour, volume.
MODES_SCRIPT = _both_merge_modes("""\
        if o.TypeId != "Part::Feature":
            continue
        shape = o.Shape
        out.append([o.Label, len(shape.Solids), all(s.isValid() for s in shape.Solids),
                    list(o.ViewObject.ShapeColor[:3]), shape.Volume])
""")

#: Per mode, each solid shown: label, type, valid, colour, volume, centre of mass, visible.
#: With merge off a shape placed several times is one hidden feature and App::Link arrays
#: placing it; with merge on, a feature per solid.
SOLIDS_SCRIPT = _both_merge_modes("""\
        if o.TypeId not in ("Part::Feature", "App::Link"):
            continue
        if any(p.TypeId == "App::Link" for p in o.InList):
            continue  # shown through the links placing it, counted there
        shape = Part.getShape(o)  # a link's shape: the linked one, placed
        colour = list(o.ViewObject.ShapeColor[:3])
        for s in shape.Solids:
            c = s.CenterOfMass
            out.append([o.Label, o.TypeId, s.isValid(), colour, s.Volume, [c.x, c.y, c.z],
                        bool(o.ViewObject.Visibility)])
""")


def check_freecad_solids(rows: list, parts, names=PART_NAMES) -> None:
    """Every solid of ``parts`` (of the parts ``names``) in FreeCAD's import: one solid
    there at its place (centre of mass within 1e-5 mm), valid, of its volume
    (1e-6 relative), in its part's colour, counted once, whether a feature or a link."""
    for name in names:
        expected = _rgb(MATERIAL_COLORS[PART_MATERIALS[name]])
        got = [r for r in rows if r[0].split(" ")[0].rstrip("0123456789") == name]
        assert len(got) == len(parts.solids[name]), name
        for solid in parts.solids[name]:
            c = solid.center()
            near = [r for r in got if max(abs(a - b) for a, b in zip(r[5], c, strict=True)) < 1e-5]
            assert len(near) == 1, (name, c)
            label, kind, valid, colour, volume, _, _ = near[0]
            assert valid, (name, label, kind)
            assert colour == pytest.approx(expected, abs=2e-3), (name, label)
            assert volume == pytest.approx(solid.volume, rel=1e-6), (name, label)


@pytest.mark.skipif(FREECAD is None, reason="FreeCAD is not installed (apt install freecad)")
def test_freecad_reads_the_folded_assembly_and_a_part_in_both_merge_modes(tmp_path):
    """Every solid of the folded sheet and of a TSA module beside it: valid, named as we
    named it, in its colour, whether STEP compound merge is on or off."""
    from build123d import Color, Compound
    from origami_cad.parts import TSAModule

    from origami_cad.fabrication.assembly import solids_by_part
    from origami_cad.fabrication.exports.step import export_step_tree

    fab = fabricate(miura_design(2, 2, 25.0, 25.0, 65.0))
    sheet = fab.assembly(0.3)
    module = TSAModule(plan=fab.plan, panel="c0r1s1")
    sheet.children[3].joints["mount"].connect_to(module.joints["mount"])
    for child in module.children:
        child.color = Color(0.25, 0.25, 0.25)
    robot = Compound(children=[sheet, module])
    robot.label = "robot"
    step = export_step_tree(robot, tmp_path / "folded.step")
    want = {
        leaf.label: (_rgb(MATERIAL_COLORS[PART_MATERIALS[part]]), leaf.volume)
        for part, leaves in solids_by_part(sheet).items()
        for leaf in leaves
    }
    want.update({c.label: ([0.25, 0.25, 0.25], c.volume) for c in module.children})
    rows = _freecad(tmp_path, MODES_SCRIPT, step)
    assert set(rows) == {"merge", "no merge"}
    for mode, features in rows.items():
        got = {
            label: (solids, valid, colour, volume)
            for label, solids, valid, colour, volume in features
        }
        assert set(got) == set(want), mode
        for label, (colour, volume) in want.items():
            solids, valid, shown, read = got[label]
            assert solids == 1 and valid, (mode, label)
            assert shown == pytest.approx(colour, abs=2e-3), (mode, label)
            assert read == pytest.approx(volume, rel=1e-6), (mode, label)
