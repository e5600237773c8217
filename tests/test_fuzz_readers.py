"""Property-based fuzzing of every reader of user files.

Hypothesis generates FOLD, SVG and DXF files and design, task and route TOML
files, from valid ones with fields replaced by hostile values (wrong types,
NaN, infinities, huge numbers and counts, junk text, deep nesting) and from
scratch. The property: every input gives a result or an
:class:`~origami_cad.errors.OrigamiCadError` whose message is one printable
line (what the CLI prints with exit code 2), within a time and memory bound;
a pattern that is read has finite, bounded coordinates and valid indices, and
can be written as FOLD, SVG and DXF and read back.

The suite runs a bounded, deterministic budget (``derandomize``; 20-30 s
here). A bigger random campaign: ``make fuzz`` (``FUZZ_EXAMPLES=1000`` per test by
default), or by hand::

    ORIGAMI_FUZZ_EXAMPLES=3000 .venv/bin/python -m pytest -q tests/test_fuzz_readers.py

The strategies hold the cases a tester's sweep found: SVG transforms that collapse the plane,
empty viewBoxes, non-finite sizes and nesting around the depth limit; DXF circles
of NaN radius, INSERT scales of 0, MINSERTs of MINSERTs and hostile grid counts
written into the file; FOLD keys given twice and fold angles against their
assignment.

Memory is measured with :mod:`tracemalloc`, which sees Python's and NumPy's
allocations (not GEOS's or ezdxf's C allocations).
"""

from __future__ import annotations

import json
import math
import os
import tempfile
import time
import tracemalloc
import xml.etree.ElementTree as ET
from pathlib import Path
from xml.sax.saxutils import quoteattr

import ezdxf
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from origami_cad.design.task import load_task
from origami_cad.errors import OrigamiCadError
from origami_cad.pattern import CreasePattern, miura_pattern, read_pattern, write_pattern
from origami_cad.pattern.design import load_design
from origami_cad.pattern.formats.svg import MAX_DEPTH
from origami_cad.pattern.model import MAX_COORDINATE
from origami_cad.strings.route import load_route

_EXAMPLES = int(os.environ.get("ORIGAMI_FUZZ_EXAMPLES", "0"))
#: a folder to keep the inputs that took over a second (for a campaign by hand)
_KEEP = os.environ.get("ORIGAMI_FUZZ_KEEP", "")
#: per-input bounds (generous: the machine is shared; typical inputs take milliseconds)
SECONDS = 10.0
PEAK_BYTES = 256 * 2**20


def fuzz(examples: int):
    """Settings of one fuzz test: ``examples`` in the suite, more by hand."""
    return settings(
        max_examples=_EXAMPLES or examples,
        deadline=None,  # the time bound is asserted below, without flaky re-runs
        derandomize=not _EXAMPLES,
        database=None,
        suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
    )


_DIR = Path(tempfile.mkdtemp(prefix="origami-fuzz-"))


@pytest.fixture(scope="module", autouse=True)
def _trace_memory():
    # first calls import modules and compile kernels: not part of any input's time
    write_pattern(miura_pattern(2, 2, 20.0, 30.0, 60.0), _DIR / "warm.dxf")
    read_pattern(_DIR / "warm.dxf")
    (_DIR / "warm.toml").write_text(toml_text(ROUTE))
    load_route(_DIR / "warm.toml", _ROUTE_CP)
    started = not tracemalloc.is_tracing()
    if started:
        tracemalloc.start()
    yield
    if started:
        tracemalloc.stop()


def outcome(load, path):
    """Run ``load(path)`` under the bounds; the result, or None for a clean refusal."""
    tracemalloc.reset_peak()
    start = time.perf_counter()
    try:
        result = load(path)
    except OrigamiCadError as exc:
        msg = str(exc)
        assert msg and msg.isprintable(), repr(msg)  # one line, no escape sequences
        assert len(msg) < 2000, len(msg)
        result = None
    elapsed = time.perf_counter() - start
    peak = tracemalloc.get_traced_memory()[1]
    if _KEEP and elapsed > 1.0:
        keep = Path(_KEEP) / f"{elapsed:07.2f}s-{time.time_ns()}{path.suffix}"
        keep.write_bytes(path.read_bytes())
    assert elapsed < SECONDS, f"{elapsed:.1f} s for {path}"
    assert peak < PEAK_BYTES, f"{peak / 2**20:.0f} MB for {path}"
    return result


def sound(cp: CreasePattern, formats=(".fold", ".svg")) -> None:
    """A pattern that was read is usable: bounded, indices valid, writable, readable."""
    assert isinstance(cp, CreasePattern)
    assert np.all(np.isfinite(cp.vertices)) and np.abs(cp.vertices).max() <= MAX_COORDINATE
    assert cp.edges.min() >= 0 and cp.edges.max() < cp.n_vertices
    assert np.all(np.abs(cp.fold_angles) <= 180 + 1e-9)
    for ext in formats:
        out = _DIR / f"back{ext}"
        try:
            write_pattern(cp, out)
        except OrigamiCadError as exc:  # e.g. a hole off every panel cannot go in a FOLD
            assert str(exc).isprintable()
            continue
        back = outcome(read_pattern, out)
        if ext == ".fold" and back is not None:
            assert back.title == cp.title


# ---------------------------------------------------------------- values
_HOSTILE_FLOATS = [math.nan, math.inf, -math.inf, 1e308, -1e308, 1e30, 5e-324, -0.0, 1e9, 2e9]
numbers = st.one_of(
    st.integers(-3, 12),
    st.floats(-20, 20, allow_nan=False).map(lambda v: round(v, 2)),
    st.sampled_from(_HOSTILE_FLOATS),
    st.integers(min_value=-(10**40), max_value=10**40),
    st.booleans(),
)
scalars = st.one_of(st.none(), numbers, st.text(max_size=6))
json_values = st.recursive(
    scalars,
    lambda inner: (
        st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=4), inner, max_size=3)
    ),
    max_leaves=12,
)


# ------------------------------------------------------------------ FOLD
@st.composite
def fold_documents(draw):
    """A small FOLD object, valid or with fields replaced by hostile values."""
    n = draw(st.integers(2, 9))
    verts = draw(st.lists(st.tuples(st.integers(0, 6), st.integers(0, 6)), min_size=n, max_size=n))
    edges = draw(
        st.lists(st.tuples(st.integers(0, n - 1), st.integers(0, n - 1)), min_size=1, max_size=12)
    )
    m = len(edges)
    doc = {
        "file_spec": 1.2,
        "file_title": draw(st.text(max_size=12)),
        "frame_unit": draw(st.sampled_from(["mm", "cm", "m", "in", "unit"])),
        "vertices_coords": [list(v) for v in verts],
        "edges_vertices": [list(e) for e in edges],
        "edges_assignment": draw(st.lists(st.sampled_from("MVBFUCJ"), min_size=m, max_size=m)),
        "edges_foldAngle": draw(
            st.lists(st.none() | st.integers(-180, 180), min_size=m, max_size=m)
        ),
    }
    if not draw(st.integers(0, 4)):  # the angles agree with their letters (B, F: flat)
        sign = {"M": -1, "V": 1, "B": 0, "F": 0}
        doc["edges_foldAngle"] = [
            None if a is None else sign.get(letter, 1) * abs(a) if letter in sign else a
            for a, letter in zip(doc["edges_foldAngle"], doc["edges_assignment"], strict=True)
        ]
    if draw(st.booleans()):
        doc["faces_vertices"] = draw(
            st.lists(st.lists(st.integers(0, n - 1), min_size=3, max_size=5), max_size=4)
        )
    if draw(st.booleans()):
        doc["file_frames"] = [
            {
                "frame_inherit": True,
                "frame_parent": 0,
                "vertices_coords": [[*v, 1.0] for v in verts],
            }
        ]
    keys = [*doc, "faces_origami_cad:holes", "faces_origami_cad:labels", "edges_foldAngles"]
    for key in draw(st.lists(st.sampled_from(keys), max_size=3, unique=True)):
        doc[key] = draw(json_values)
    for _ in range(draw(st.integers(0, 2))):  # one value deep inside a list
        key = draw(st.sampled_from(["vertices_coords", "edges_vertices", "faces_vertices"]))
        rows = doc.get(key)
        if isinstance(rows, list) and rows and isinstance(rows[0], list) and rows[0]:
            i = draw(st.integers(0, len(rows) - 1))
            if isinstance(rows[i], list) and rows[i]:
                rows[i][draw(st.integers(0, len(rows[i]) - 1))] = draw(numbers | scalars)
    return doc


@fuzz(80)
@given(doc=fold_documents(), nest=st.integers(0, 3))
def test_fuzz_fold_reader(doc, nest):
    text = json.dumps(doc, allow_nan=True)
    if nest == 3:  # deep nesting somewhere
        text = text[:-1] + ', "x": ' + "[" * 50_000 + "]" * 50_000 + "}"
    path = _DIR / "fuzz.fold"
    path.write_text(text, encoding="utf-8", errors="surrogatepass")
    cp = outcome(read_pattern, path)
    if cp is not None:
        sound(cp)


@fuzz(80)
@given(doc=fold_documents(), heights=st.lists(st.integers(0, 6), min_size=9, max_size=9))
def test_fuzz_folded_forms(doc, heights):
    # a key frame in 3D: a folded form the reader unfolds (faces laid flat, or refused)
    coords = doc["vertices_coords"]
    if isinstance(coords, list) and all(isinstance(c, list) and len(c) == 2 for c in coords):
        doc["vertices_coords"] = [[*c, heights[k % 9]] for k, c in enumerate(coords)]
    doc["frame_classes"] = ["foldedForm"]
    path = _DIR / "fuzz_form.fold"
    path.write_text(json.dumps(doc, allow_nan=True), encoding="utf-8", errors="surrogatepass")
    cp = outcome(read_pattern, path)
    if cp is not None:
        sound(cp)


@fuzz(40)
@given(doc=fold_documents(), key=st.integers(0, 20), value=json_values, same=st.booleans())
def test_fuzz_fold_duplicate_keys(doc, key, value, same):
    # a key given twice: the same value reads, a different one is refused naming the key
    name = sorted(doc)[key % len(doc)]
    again = doc[name] if same else value
    text = json.dumps(doc, allow_nan=True)[:-1] + f", {json.dumps(name)}: "
    path = _DIR / "fuzz_dup.fold"
    path.write_text(text + json.dumps(again, allow_nan=True) + "}", encoding="utf-8")
    try:
        json.loads(path.read_text(), object_pairs_hook=_no_duplicates)
        contradicts = False
    except KeyError:
        contradicts = True
    cp = outcome(read_pattern, path)
    if contradicts:
        assert cp is None
    elif cp is not None:
        sound(cp)


def _no_duplicates(pairs):
    seen = {}
    for k, v in pairs:
        if k in seen and seen[k] != v:
            raise KeyError(k)
        seen[k] = v
    return seen


@fuzz(40)
@given(doc=fold_documents(), cut=st.integers(0, 10_000), junk=st.text(max_size=4))
def test_fuzz_fold_text(doc, cut, junk):
    text = json.dumps(doc)
    k = cut % (len(text) + 1)
    path = _DIR / "fuzz.fold"
    path.write_text(text[:k] + junk + text[k + len(junk) :], encoding="utf-8", errors="replace")
    cp = outcome(read_pattern, path)
    if cp is not None:
        sound(cp)


# ------------------------------------------------------------------- SVG
_num_text = st.one_of(
    st.integers(-5, 120).map(str),
    st.sampled_from(
        ["1e999", "-1e400", "nan", "inf", "1e9", "5e8", ".5.5", "1-2", "--1", "1e", ""]
    ),
    st.floats(-200, 200, allow_nan=False).map(lambda v: f"{v:.3f}"),
)
_path_tokens = st.one_of(
    st.sampled_from([*"MmLlHhVvZzCcQqAaXx", ",", " ", "#", "e"]),
    _num_text,
)
_path_data = st.lists(_path_tokens, max_size=14).map(" ".join)
_transforms = st.lists(
    st.tuples(
        st.sampled_from(["matrix", "translate", "scale", "rotate", "skewX", "skewY", "spin", ""]),
        st.lists(_num_text, max_size=7),
    ).map(lambda t: f"{t[0]}({','.join(t[1])})")
    | st.sampled_from(["scale(0)", "scale(1 0)", "matrix(1 2 2 4 0 0)", "skewX(90)", "scale(-1)"]),
    max_size=3,
).map(" ".join)
_colours = st.sampled_from(
    ["black", "red", "blue", "#f00", "#0000ff", "#00ff00", "#ffff00", "magenta", "none",
     "rgb(255,0,0)", "rgb(100%, 0%, 0%)", "rgb(1e999,0,0)", "rgb(a,b,c)", "#12", "pink", ""]
)  # fmt: skip
_opacities = st.one_of(_num_text, st.sampled_from(["50%", "150%", "0.5", "5", "-1", "1"]))
_xml_text = st.text(
    alphabet=st.characters(blacklist_categories=("Cs", "Cc")) | st.sampled_from("\n\t"), max_size=8
)
_ATTRS = {
    "x1": _num_text, "y1": _num_text, "x2": _num_text, "y2": _num_text,
    "d": _path_data, "points": st.lists(_num_text, max_size=8).map(" ".join),
    "transform": _transforms, "stroke": _colours, "fill": _colours,
    "stroke-opacity": _opacities, "opacity": _opacities, "id": _xml_text,
    "x": _num_text, "y": _num_text, "width": _num_text, "height": _num_text,
    "cx": _num_text, "cy": _num_text, "r": _num_text,
    "style": st.tuples(_colours, _opacities).map(lambda t: f"stroke:{t[0]};stroke-opacity:{t[1]}"),
}  # fmt: skip
_TAGS = ["line", "path", "polyline", "polygon", "rect", "circle", "g", "title", "defs", "text"]


@st.composite
def svg_elements(draw, depth=0):
    tag = draw(st.sampled_from(_TAGS))
    el = ET.Element(tag)
    for key in draw(st.lists(st.sampled_from(sorted(_ATTRS)), max_size=6, unique=True)):
        el.set(key, draw(_ATTRS[key]))
    if tag == "title":
        el.text = draw(_xml_text)
    if tag in ("g", "defs") and depth < 3:
        el.extend(draw(st.lists(svg_elements(depth=depth + 1), max_size=3)))
    return el


_GOOD = [
    ET.Element("line", x1="0", y1="0", x2="100", y2="0", stroke="black"),
    ET.Element("path", d="M 100 0 V 100 H 0 Z", stroke="#000"),
    ET.Element("line", x1="0", y1="0", x2="100", y2="100", stroke="blue"),
]


@fuzz(80)
@given(
    root_attrs=st.dictionaries(st.sampled_from(["width", "height", "viewBox"]), _num_text),
    units=st.sampled_from(["", "mm", "px", "in", "%", "em"]),
    good=st.booleans(),
    children=st.lists(svg_elements(), max_size=5),
    nest=st.sampled_from([0, 0, 0, 5, MAX_DEPTH - 3, MAX_DEPTH + 1, 20_000]),
    groups=st.lists(_transforms, max_size=3),
)
def test_fuzz_svg_reader(root_attrs, units, good, children, nest, groups):
    root = ET.Element("svg", xmlns="http://www.w3.org/2000/svg")
    for k, v in root_attrs.items():
        root.set(k, v + units if k != "viewBox" else f"0 0 {v} {v}")
    if good:
        root.extend(_GOOD)
    root.append(ET.Element("nested"))  # where the nested groups go, written as text below:
    # ElementTree writes recursively, and 20,000 levels would overflow the test's own stack
    opens = [f"<g transform={quoteattr(t)}>" for t in groups[:nest]] + ["<g>"] * nest
    inner = "".join(ET.tostring(c, encoding="unicode") for c in children)
    text = ET.tostring(root, encoding="unicode").replace(
        "<nested />", "".join(opens[:nest]) + inner + "</g>" * nest
    )
    path = _DIR / "fuzz.svg"
    path.write_text(text, encoding="utf-8", errors="surrogatepass")
    cp = outcome(read_pattern, path)
    if cp is not None:
        sound(cp)


# ------------------------------------------------------------------- DXF
_coord = st.one_of(
    st.integers(-50, 150).map(float),
    st.sampled_from([1e300, -1e300, 1e12, 1e9, 1e-300, 0.0, math.nan, math.inf]),
)
_point = st.tuples(_coord, _coord)
_LAYERS = ["Mountain", "Valley", "Border", "Cut", "Holes", "0", "Misc", "Flat"]


@st.composite
def dxf_documents(draw):
    units = draw(st.sampled_from([0, 1, 4, 6, 99]))
    doc = ezdxf.new("R2010")
    doc.header["$INSUNITS"] = units
    msp = doc.modelspace()
    blk = doc.blocks.new("B")
    inner = doc.blocks.new("C")
    inner.add_line((0, 0), (1, 1), dxfattribs={"layer": "0"})
    grid = doc.blocks.new("D")  # a MINSERT inside a block: a MINSERT of it nests two grids
    grid.add_blockref("C", (0, 0)).grid(
        size=(draw(st.integers(1, 6)), draw(st.integers(1, 6))), spacing=(2.0, 3.0)
    )
    targets = [msp, msp, msp, blk]
    for _ in range(draw(st.integers(0, 8))):
        try:
            _add_entity(draw, msp, draw(st.sampled_from(targets)))
        except (ezdxf.DXFError, ValueError, TypeError, IndexError, ArithmeticError):
            pass  # ezdxf refuses to draw it: not a file we can be given
    return doc


def _add_entity(draw, msp, where):
    attribs = {"layer": draw(st.sampled_from(_LAYERS)), "color": draw(st.integers(0, 256))}
    kind = draw(st.sampled_from(["line", "lwpoly", "circle", "arc", "ellipse", "spline", "ref"]))
    if kind == "line":
        where.add_line(draw(_point), draw(_point), dxfattribs=attribs)
    elif kind == "lwpoly":
        pts = draw(st.lists(st.tuples(_coord, _coord, st.just(0), st.just(0), _coord), max_size=5))
        where.add_lwpolyline(pts, format="xyseb", close=draw(st.booleans()), dxfattribs=attribs)
    elif kind == "circle":
        where.add_circle(draw(_point), draw(_coord), dxfattribs=attribs)
    elif kind == "arc":
        where.add_arc(draw(_point), draw(_coord), draw(_coord), draw(_coord), dxfattribs=attribs)
    elif kind == "ellipse":
        ratio = draw(st.sampled_from([0.5, 1.0, 1e-9]))
        where.add_ellipse(draw(_point), (draw(_coord), 1.0, 0.0), ratio, dxfattribs=attribs)
    elif kind == "spline":
        where.add_spline(draw(st.lists(_point, min_size=2, max_size=5)), dxfattribs=attribs)
    elif where is msp:
        name = draw(st.sampled_from(["B", "C", "D"]))
        ref = msp.add_blockref(name, draw(_point), dxfattribs=attribs)
        ref.dxf.xscale = draw(st.sampled_from([1.0, -1.0, 0.0, 1e200, 2.0]))
        if draw(st.booleans()):
            rows, cols = draw(st.integers(-1, 4000)), draw(st.integers(-1, 4000))
            ref.grid(size=(max(rows, 1), max(cols, 1)), spacing=(draw(_coord), draw(_coord)))


@fuzz(30)
@given(doc=dxf_documents(), square=st.booleans())
def test_fuzz_dxf_reader(doc, square):
    if square:
        msp = doc.modelspace()
        msp.add_lwpolyline([(0, 0), (100, 0), (100, 100), (0, 100)], close=True,
                           dxfattribs={"layer": "Border"})  # fmt: skip
        msp.add_line((0, 0), (100, 100), dxfattribs={"layer": "Valley"})
    path = _DIR / "fuzz.dxf"
    try:
        doc.saveas(path)
    except (ValueError, TypeError, OverflowError, ArithmeticError):
        return  # ezdxf refused to write what was drawn: not an input we can be given
    cp = outcome(read_pattern, path)
    if cp is not None:
        sound(cp, (".fold", ".dxf"))


#: DXF group codes of an INSERT's numbers: scales, rotation, grid counts and spacings
_INSERT_GROUPS = [" 41", " 42", " 50", " 70", " 71", " 44", " 45", " 10", " 40"]


@fuzz(30)
@given(
    doc=dxf_documents(),
    group=st.sampled_from(_INSERT_GROUPS),
    k=st.integers(0, 50),
    value=st.sampled_from(["0", "-3", "0.0", "nan", "inf", "-1e308", "100000", "1e-320"]),
)
def test_fuzz_dxf_numbers_of_the_file(doc, group, k, value):
    # ezdxf never writes a zero scale, a negative grid count or NaN: edit them in
    msp = doc.modelspace()
    msp.add_lwpolyline([(0, 0), (100, 0), (100, 100), (0, 100)], close=True,
                       dxfattribs={"layer": "Border"})  # fmt: skip
    ref = msp.add_blockref("D", (10, 10), dxfattribs={"xscale": 2.0, "rotation": 30.0})
    ref.grid(size=(2, 3), spacing=(20.0, 25.0))
    path = _DIR / "fuzz_numbers.dxf"
    try:
        doc.saveas(path)
    except (ValueError, TypeError, OverflowError, ArithmeticError):
        return
    lines = path.read_text(encoding="utf-8").splitlines()
    at = [i for i, line in enumerate(lines[:-1]) if line == group]
    if at:
        lines[at[k % len(at)] + 1] = value
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    cp = outcome(read_pattern, path)
    if cp is not None:
        sound(cp, (".fold", ".dxf"))


@fuzz(25)
@given(
    line=st.integers(0, 10_000),
    junk=st.sampled_from(["", "nan", "1e999", "-5", "X", "0", "\x00", "INSERT"]),
)
def test_fuzz_dxf_text(line, junk):
    base = _DIR / "base.dxf"
    if not base.exists():
        write_pattern(miura_pattern(2, 2, 20.0, 30.0, 60.0), base)
    lines = base.read_text(encoding="utf-8").splitlines()
    lines[line % len(lines)] = junk
    path = _DIR / "fuzz.dxf"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    cp = outcome(read_pattern, path)
    if cp is not None:
        sound(cp)


# ------------------------------------------------------------------ TOML
def toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return (
            "{" + ", ".join(f"{json.dumps(str(k))} = {toml_value(x)}" for k, x in v.items()) + "}"
        )
    return '""'  # None has no TOML form


def toml_text(doc: dict) -> str:
    """TOML for {table: {key: value}} (arrays of tables as lists of dicts)."""
    out = []
    for name, table in doc.items():
        if not isinstance(table, dict):
            out.append(f"{name} = {toml_value(table)}")
            continue
        plain = {
            k: v
            for k, v in table.items()
            if not (isinstance(v, list) and v and all(isinstance(x, dict) for x in v))
        }
        out.append(f"[{name}]")
        out += [f"{json.dumps(k)} = {toml_value(v)}" for k, v in plain.items()]
        for k, v in table.items():
            if k not in plain:
                for item in v:
                    out.append(f"[[{name}.{k}]]")
                    out += [f"{json.dumps(kk)} = {toml_value(vv)}" for kk, vv in item.items()]
    return "\n".join(out) + "\n"


toml_values = st.recursive(
    st.one_of(numbers, st.text(max_size=5)),
    lambda inner: (
        st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=3), inner, max_size=2)
    ),
    max_leaves=10,
)


def mutated(base: dict, table: str):
    @st.composite
    def strategy(draw):
        doc = json.loads(json.dumps(base))
        keys = sorted(doc[table])
        for key in draw(st.lists(st.sampled_from([*keys, "extra"]), max_size=3, unique=True)):
            doc[table][key] = draw(toml_values)
        return doc

    return strategy()


DESIGNS = [
    {"pattern": {"kind": "miura", "rows": 2, "columns": 3, "panel_length": 20.0,
                 "panel_width": 30.0, "sector_angle": 70.0}},
    {"pattern": {"kind": "transition-graph", "unit_width": 36.0, "copies": 2, "entry_flag": 1,
                 "start": [0.0, 0.0], "fold_ratio": 0.5,
                 "vectors": [[40, 0], [30, 25], [30, -10]]}},
    {"pattern": {"kind": "transition-graph", "unit_width": 36.0, "copies": 2, "entry_flag": 0,
                 "lengths": [30.0, 40.0], "shape_angles": [60.0]}},
]  # fmt: skip
TASK = {
    "arm": {"start": [0.0, 0.0], "points": [[250.0, 0.0], [50.0, 133.3]], "alpha": 120.0,
            "vectors": 6, "length_range": [10.0, 120.0], "shape_angle_range": [10.0, 80.0],
            "entry_flag": "both", "samples": 46, "unit_width": 36.0, "min_leg_gap": 2.0,
            "warning": [{"polygon": [[140, 30], [2000, 30], [2000, 2000], [140, 2000]]}],
            "prohibited": [{"circle": [150, 40, 30]}]},
    "search": {"runs": 2, "seed": 1, "popsize": 0, "max_generations": 40, "sigma0": 0.25},
}  # fmt: skip
ROUTE = {
    "tsa": {"model": "ring", "d1": 10.0, "d2": 8.0, "string_width": 0.5},
    "route": {"thickness": 2.2, "step": 2.0, "max_turns": 40, "p_max": 0.8,
              "strings": [{"anchor": [10.0, 10.0, 20.0], "holes": ["c0r0s0", [30.0, 15.0]],
                           "sides": "auto"}]},
}  # fmt: skip
_ROUTE_CP = miura_pattern(2, 3, 20.0, 30.0, 70.0)


@fuzz(50)
@given(doc=st.one_of(*(mutated(d, "pattern") for d in DESIGNS)))
def test_fuzz_design_loader(doc):
    path = _DIR / "design.toml"
    path.write_text(toml_text(doc), encoding="utf-8", errors="surrogatepass")
    design = outcome(load_design, path)
    if design is not None:
        sound(design.pattern)


@fuzz(40)
@given(doc=st.one_of(mutated(TASK, "arm"), mutated(TASK, "search")))
def test_fuzz_task_loader(doc):
    path = _DIR / "task.toml"
    path.write_text(toml_text(doc), encoding="utf-8", errors="surrogatepass")
    got = outcome(load_task, path)
    if got is not None:
        task, search = got
        assert np.all(np.isfinite(task.points)) and 0 <= search.seed < 2**32 - search.runs


@fuzz(40)
@given(doc=st.one_of(mutated(ROUTE, "route"), mutated(ROUTE, "tsa")), string=toml_values)
def test_fuzz_route_loader(doc, string):
    if isinstance(string, dict):
        doc["route"]["strings"] = [string]
    path = _DIR / "route.toml"
    path.write_text(toml_text(doc), encoding="utf-8", errors="surrogatepass")
    outcome(lambda p: load_route(p, _ROUTE_CP), path)


@fuzz(30)
@given(text=st.text(max_size=60))
def test_fuzz_toml_text(text):
    path = _DIR / "raw.toml"
    path.write_text("[pattern]\n" + text, encoding="utf-8", errors="surrogatepass")
    outcome(load_design, path)
