"""Hostile and careless SVG files, and markup injection.

The SVGs are written here. Malformed path data, transforms, colours and opacities
give a PatternError naming the file and the element, on one line; what the
package writes into XML (the SVG title) or HTML (the demo report) is escaped, so a
real XML/HTML parser reads back the text and finds no injected element.
"""

from __future__ import annotations

import html.parser
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from conftest import refused as refused_by

from origami_cad.errors import PatternError
from origami_cad.pattern import miura_pattern, read_pattern, write_pattern
from origami_cad.pattern.formats.svg import MAX_DEPTH, read_svg
from origami_cad.viz.report import StepReport, write_report

HEAD = '<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="100mm" viewBox="0 0 100 100">'
BORDER = '<rect x="0" y="0" width="100" height="100" stroke="black" fill="none"/>'


def svg(tmp_path, body, name="bad.svg", head=HEAD):
    p = tmp_path / name
    p.write_text(f"{head}{BORDER}{body}</svg>", encoding="utf-8")
    return p


def refused(path, *fragments):
    return refused_by(read_svg, path, *fragments, error=PatternError)


def valley(body_attrs):
    return f'<path stroke="blue" {body_attrs}/>'


@pytest.mark.parametrize(
    "d, fragment",
    [
        ("M 0 0 L 100 100 junk", "'j' is not a path command"),
        ("M 0 0 L 100 100 # 5 5", "'# 5 5'"),
        ("M 0 0 L 100", "'L' needs 2 numbers"),
        ("M 0", "'M' needs 2 numbers"),
        ("M 0 0 L", "has no coordinates"),
        ("L 100 100 M", "has no coordinates"),
        ("M 0 0 X 5 5", "'X' is not a path command"),
        ("M 0 0 L 1e999 5", "out of range"),
        ("M 0 0 L 5e9 5", "out of range"),
        ("M 0 0 Z 5 5", "a number after 'Z'"),
        ("10 10 L 0 0", "must start with a command"),
        ("M 0 0 c 5 5 10 10", "'c' needs 6 numbers"),
        ("M 0 0 L 10 10 A 5 5 0 0 1 20", "'A' needs 7 numbers"),
    ],
)
def test_malformed_path_data_is_refused(tmp_path, d, fragment):
    refused(svg(tmp_path, valley(f'id="p1" d="{d}"')), "<path id=p1>", fragment)


def test_junk_inside_path_data_is_not_skipped(tmp_path):
    # the old reader skipped "q" and read this as a straight valley from (0,0) to (100,100)
    refused(svg(tmp_path, valley('d="M 0 0 q L 100 100"')), "path")


@pytest.mark.parametrize(
    "transform, fragment",
    [
        ("translate()", "takes 1 or 2 numbers, got 0"),
        ("matrix(1 0 0 1 0)", "takes 6 numbers, got 5"),
        ("rotate(1 2)", "takes 1 or 3 numbers, got 2"),
        ("scale(1e999)", "out of range"),
        ("scale(1e9) " * 40, "overflows"),
        ("translate(5,x)", "not a list of numbers"),
        ("spin(30)", "unknown transform 'spin'"),
        ("translate(5) garbage", "malformed at character"),
    ],
)
def test_malformed_transforms_are_refused(tmp_path, transform, fragment):
    body = valley(f'd="M 0 0 L 100 100" transform="{transform}"')
    refused(svg(tmp_path, body), fragment)
    # on a group too
    inner = valley("d='M 0 0 L 9 9'")
    refused(svg(tmp_path, f'<g transform="{transform}">{inner}</g>'), fragment)


@pytest.mark.parametrize(
    "attrs, fragment",
    [
        ('stroke="rgb(1e999, 0, 0)"', "out of range"),
        ('stroke="rgb(a, b, c)"', "is not a number"),
        ('stroke="rgb(255, 0, 0" ', "not a crease colour"),
        ('stroke="#12"', "not a crease colour"),
        ('stroke="blue" stroke-opacity="5"', "outside [0, 1]"),
        ('stroke="red" stroke-opacity="-0.5"', "outside [0, 1]"),
        ('stroke="red" stroke-opacity="150%"', "outside [0, 1]"),
        ('stroke="red" stroke-opacity="half"', "is not a number"),
        ('stroke="red" opacity="NaN"', "is not a number"),
        ('stroke="red" style="stroke-opacity: 1e400"', "out of range"),
    ],
)
def test_malformed_colours_and_opacities_are_refused(tmp_path, attrs, fragment):
    refused(svg(tmp_path, f'<line x1="0" y1="0" x2="100" y2="100" {attrs}/>'), fragment)


def test_opacity_five_no_longer_gives_a_900_degree_fold(tmp_path):
    refused(
        svg(tmp_path, '<line x1="0" y1="0" x2="100" y2="100" stroke="red" stroke-opacity="5"/>')
    )
    ok = read_svg(
        svg(tmp_path, '<line x1="0" y1="0" x2="100" y2="100" stroke="red" stroke-opacity="50%"/>')
    )
    assert sorted(ok.fold_angles.tolist())[0] == -90.0


@pytest.mark.parametrize(
    "element, fragment",
    [
        ('<line x1="0" y1="0" x2="inf" y2="100" stroke="blue"/>', "x2 = 'inf' is not a number"),
        ('<line x1="0" y1="0" x2="1e999" y2="100" stroke="blue"/>', "out of range"),
        ('<line x1="0" y1="0" x2="5mm" y2="100" stroke="blue"/>', "x2 = '5mm' is not a number"),
        ('<polyline points="0,0 100,100 50" stroke="blue"/>', "odd count"),
        ('<polyline points="0,0 100,100 x,y" stroke="blue"/>', "not a list of numbers"),
        ('<rect x="0" y="0" width="-5" height="5" stroke="blue"/>', "must be >= 0"),
        ('<circle cx="50" cy="50" r="-2" fill="black"/>', "diameter must be > 0"),
        ('<circle cx="nan" cy="50" r="2" fill="black"/>', "cx = 'nan' is not a number"),
    ],
)
def test_malformed_numbers_are_refused(tmp_path, element, fragment):
    refused(svg(tmp_path, element), fragment)


@pytest.mark.parametrize(
    "head, fragment",
    [
        ('<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100">', "viewBox must be 4"),
        ('<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 -1 100">', "viewBox must be 4"),
        (
            '<svg xmlns="http://www.w3.org/2000/svg" width="1e999mm" height="1mm" '
            'viewBox="0 0 1 1">',
            "out of range",
        ),
    ],
)
def test_malformed_root_sizes_are_refused(tmp_path, head, fragment):
    refused(svg(tmp_path, "", head=head), fragment)


def test_a_transform_that_throws_points_past_the_limit_is_refused(tmp_path):
    body = valley('d="M 0 0 L 100 100" transform="scale(1e8)"')
    refused(svg(tmp_path, body), "farther than 1e+09 mm")


def test_deeply_nested_groups_read_up_to_the_depth_limit(tmp_path):
    depth = MAX_DEPTH - 2  # below the root and the border's level, the line on the last
    body = "<g>" * depth + '<line x1="0" y1="0" x2="100" y2="100" stroke="blue"/>' + "</g>" * depth
    cp = read_svg(svg(tmp_path, body, "deep.svg"))
    assert int((cp.assignments == "V").sum()) == 1 and len(cp.faces) == 2
    body = (
        "<g>" * (depth + 1)
        + '<line x1="0" y1="0" x2="1" y2="1" stroke="blue"/>'
        + "</g>" * (depth + 1)
    )
    refused(svg(tmp_path, body, "deeper.svg"), f"deeper than the limit of {MAX_DEPTH}")


def test_an_id_with_a_newline_cannot_forge_message_lines(tmp_path):
    ident = "x&#10;origami-cad: everything is fine&#13;&#9;"
    msg = refused(svg(tmp_path, f'<line id="{ident}" x1="0" y1="0" x2="1" y2="1" stroke="#123"/>'))
    assert "\n" not in msg and "\r" not in msg and "\t" not in msg
    assert "x\\norigami-cad: everything is fine" in msg


@pytest.mark.parametrize(
    "title",
    [
        "</title><script>alert(1)</script>",
        'Tom & Jerry\'s <fold> "1"',
        "]]><![CDATA[",
        "bell\x07 escape\x1b nul-free \ud800 lone surrogate",
    ],
)
def test_titles_are_escaped_in_the_svg_we_write(tmp_path, title):
    cp = miura_pattern(2, 3, 20.0, 30.0, 60.0).with_metadata(title=title)
    path = write_pattern(cp, tmp_path / "out.svg")
    root = ET.parse(path).getroot()  # a real XML parser accepts the file
    tags = {el.tag.rsplit("}", 1)[-1] for el in root.iter()}
    assert "script" not in tags
    back = read_pattern(path)  # and so does our reader
    printable_in = "".join(c if c.isprintable() else "\ufffd" for c in title)
    assert back.title in (title, printable_in)
    assert back.same_graph(cp)


def test_titles_and_messages_are_escaped_in_the_report(tmp_path):
    evil = "</title><script>alert('x')</script>&\x07\ud800"
    step = StepReport(
        key="k'><script>",
        title=evil,
        summary=evil,
        numbers=[(evil, evil)],
        images=[("javascript:alert(1)", evil)],
        files=["javascript:alert(1)", "a b.fold"],
        error=evil,
    )
    path = write_report(tmp_path / "report.html", [step], title=evil, subtitle=evil)
    text = path.read_text(encoding="utf-8")

    class Collect(html.parser.HTMLParser):
        def __init__(self):
            super().__init__()
            self.tags, self.links = [], []

        def handle_starttag(self, tag, attrs):
            self.tags.append(tag)
            self.links += [v for k, v in attrs if k in ("href", "src")]

    parser = Collect()
    parser.feed(text)
    assert "script" not in parser.tags
    assert parser.links and all(not v.startswith("javascript:") for v in parser.links)
    assert "</title><script>" not in text


def test_a_deep_zero_scale_is_refused_not_dropped(tmp_path):
    # a degenerate transform collapses the lines to points: refused, naming the element
    inner = valley("id='gone' d='M 0 0 L 9 9'")
    body = f'<g transform="scale(0)">{inner}</g>'
    refused(svg(tmp_path, body, "zero.svg"), "<path id=gone>", "collapses the plane")


@pytest.mark.parametrize(
    "attr, value",
    [
        ("points", "1" * 200_000 + "x"),
        ("points", "1." * 100_000 + "x"),
        ("d", "M 0 0 " + "L 1 1 " * 50_000 + "#"),
        ("transform", "scale(" + "1 " * 100_000 + ")"),
        ("stroke", "rgb(1, " + " " * 100_000 + "x"),
    ],
)
def test_long_malformed_attributes_are_refused_in_linear_time(tmp_path, attr, value):
    # a backtracking pattern would take hours on these (the old number pattern did)
    body = f'<polyline points="0 0 100 100" stroke="blue" {attr}="{value}"/>'
    if attr == "d":
        body = f'<path stroke="blue" d="{value}"/>'
    refused(svg(tmp_path, body))


@pytest.mark.parametrize(
    "element",
    [
        '<circle cx="50" cy="50" r="20" stroke="red" fill="none"/>',
        '<ellipse cx="50" cy="50" rx="20" ry="10" stroke="black"/>',
    ],
)
def test_stroked_circles_and_ellipses_are_not_silently_dropped(tmp_path, element):
    """Origami Simulator reads no circle or ellipse as a crease: left out, with a warning
    that names the element (HexSpiralTess.svg draws its sheet's round edge so)."""
    crease = '<line x1="0" y1="50" x2="100" y2="50" stroke="red"/>'
    cp = read_svg(svg(tmp_path, crease + element))
    assert cp.n_edges == read_svg(svg(tmp_path, crease, "plain.svg")).n_edges
    (note,) = [n for n in cp.notes if n.code == "curve-element"]
    assert note.severity == "warning" and "(element 4)" in note.message
    # a filled circle without a stroke is still a hole
    hole = read_svg(svg(tmp_path, '<circle cx="50" cy="50" r="2" fill="black"/>', "hole.svg"))
    assert [(h.x, h.y, h.diameter) for h in hole.holes] == [(50.0, -50.0, 4.0)]


XLINK_HEAD = HEAD.replace("<svg ", '<svg xmlns:xlink="http://www.w3.org/1999/xlink" ')


def test_use_draws_what_it_names_moved_by_x_y_and_its_transform(tmp_path):
    """``<use>`` (href or xlink:href, of a group or a symbol) gives the same pattern as the
    same lines written out, as a browser or Inkscape draws it."""
    cell = '<g id="cell"><line x1="0" y1="0" x2="50" y2="0" stroke="#ff0000"/></g>'
    sym = '<symbol id="col"><line x1="0" y1="0" x2="0" y2="50" stroke="#0000ff"/></symbol>'
    used = svg(
        tmp_path,
        f"<defs>{cell}{sym}</defs>"
        '<use href="#cell" y="50"/><use xlink:href="#cell" x="50" y="50"/>'
        '<use href="#col" x="50" transform="translate(0 10)" stroke-opacity="0.5"/>',
        "use.svg",
        XLINK_HEAD,
    )
    plain = svg(
        tmp_path,
        '<line x1="0" y1="50" x2="50" y2="50" stroke="#ff0000"/>'
        '<line x1="50" y1="50" x2="100" y2="50" stroke="#ff0000"/>'
        '<line x1="50" y1="10" x2="50" y2="60" stroke="#0000ff"/>',
        "plain.svg",
    )
    a, b = read_svg(used), read_svg(plain)
    assert a.n_edges == b.n_edges
    assert sorted(a.assignments).count("M") == 2 and sorted(a.assignments).count("V") == 2
    key = lambda cp: sorted(  # noqa: E731
        (tuple(sorted(map(tuple, cp.vertices[e].round(9).tolist()))), s)
        for e, s in zip(cp.edges, cp.assignments, strict=True)
    )
    assert key(a) == key(b)


@pytest.mark.parametrize(
    "body, fragment",
    [
        ('<use id="u" href="#nothing"/>', "href '#nothing' names no element"),
        ('<use href="other.svg#cell"/>', "names no element of this file"),
        ('<g id="loop"><use href="#loop"/></g>', "#loop contains this <use> (a cycle)"),
        ('<use href="#cell" x="1e400"/><g id="cell"/>', "x"),
    ],
)
def test_bad_use_elements_are_refused_by_name(tmp_path, body, fragment):
    refused(svg(tmp_path, body), fragment)


def test_use_that_multiplies_elements_is_refused_before_it_explodes(tmp_path):
    """A "billion laughs" of nested <use>: 10 copies of 10 copies ... of one line."""
    body = '<g id="l0"><line x1="0" y1="0" x2="1" y2="1" stroke="red"/></g>'
    for k in range(1, 8):
        uses = "".join(f'<use href="#l{k - 1}"/>' for _ in range(10))
        body += f'<g id="l{k}">{uses}</g>'
    # 10 million lines: the first of the two bounds that is reached stops the walk
    msg = refused(svg(tmp_path, f"<defs>{body}</defs><use href='#l7'/>"), "more than")
    assert "1,000,000 elements" in msg or "100,000 line segments (MAX_EDGES)" in msg


def _curve_sheet(tmp_path, d: str):
    """A 100 x 100 sheet whose valley crease is the path ``d`` from (0, 50) to (100, 50)."""
    body = (
        '<rect x="0" y="0" width="100" height="100" fill="none" stroke="#000000"/>'
        f'<path d="{d}" fill="none" stroke="#0000ff"/>'
    )
    path = tmp_path / "curve.svg"
    path.write_text(
        '<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="100mm" '
        f'viewBox="0 0 100 100">{body}</svg>'
    )
    return read_svg(path)


def _cubic(t):
    return (
        3 * (1 - t) ** 2 * t * 25 + 3 * (1 - t) * t**2 * 75 + t**3 * 100,
        (1 - t) ** 3 * 50 + 3 * (1 - t) ** 2 * t * 20 + 3 * (1 - t) * t**2 * 80 + t**3 * 50,
    )


def _quadratic(t):
    return 100 * t, (1 - t) ** 2 * 50 + 2 * (1 - t) * t * 10 + t**2 * 50


def _half_circle(t):
    return 50 - 50 * np.cos(np.pi * t), 50 - 50 * np.sin(np.pi * t)


@pytest.mark.parametrize(
    "d, on_curve",
    [
        ("M 0 50 C 25 20 75 80 100 50", _cubic),
        ("M 0 50 Q 50 10 100 50", _quadratic),
        ("M 0 50 A 50 50 0 0 1 100 50", _half_circle),
    ],
)
def test_curved_creases_are_cut_into_straight_segments(tmp_path, d, on_curve):
    # a cubic, a quadratic and a half circle (arc): every vertex of the polyline on the
    # exact curve, and the polyline as long as the curve within 0.5 %
    cp = _curve_sheet(tmp_path, d)
    valleys = cp.edge_mask("V")
    assert valleys.sum() >= 4  # a polyline of several straight creases
    assert not [p for p in cp.check() if p.severity == "error"]
    ends = cp.vertices[cp.edges[valleys]].reshape(-1, 2)
    # every vertex of the polyline lies on the curve (SVG's y is the pattern's -y)
    exact = np.array([on_curve(t) for t in np.linspace(0, 1, 2001)])
    exact[:, 1] = -exact[:, 1]
    gap = np.min(np.linalg.norm(ends[:, None, :] - exact[None, :, :], axis=2), axis=1)
    assert gap.max() < 0.1
    # and the polyline's length is the curve's within 0.5 %
    arc = float(np.sum(np.linalg.norm(np.diff(exact, axis=0), axis=1)))
    assert cp.edge_lengths()[valleys].sum() == pytest.approx(arc, rel=5e-3)


def test_a_smooth_curve_continues_its_last_control_point(tmp_path):
    # S reflects the previous C's second control point: the wave is symmetric about x = 50
    cp = _curve_sheet(tmp_path, "M 0 50 C 10 20 40 20 50 50 S 90 80 100 50")
    valleys = cp.vertices[np.unique(cp.edges[cp.edge_mask("V")])]
    top = valleys[valleys[:, 0] < 50]
    bottom = valleys[valleys[:, 0] > 50]
    assert np.min(-top[:, 1]) < 35  # the first half bows toward its control points (y 20)
    assert np.max(-bottom[:, 1]) > 50 + 15  # the reflected half bows the other way
