"""SVG style sheets: crease colours given by ``<style>`` rules, as Illustrator's default
export ("Style Elements") writes them, resolved in CSS's cascade."""

from __future__ import annotations

import numpy as np
import pytest

from origami_cad.pattern import read_pattern
from origami_cad.pattern.formats.svg import read_svg

HEAD = '<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="100mm" viewBox="0 0 100 100">'


def write(tmp_path, style, body, name="styled.svg"):
    p = tmp_path / name
    border = '<rect class="edge" x="0" y="0" width="100" height="100" fill="none"/>'
    p.write_text(f"{HEAD}<style>{style}</style>{border}{body}</svg>", encoding="utf-8")
    return p


def letters(cp):
    """The crease letters of a pattern, sorted (border edges left out)."""
    return sorted(str(a) for a in cp.assignments if a != "B")


def test_illustrator_class_rules_colour_the_creases(tmp_path):
    style = (
        ".edge{fill:none;stroke:#000000;}\n"
        ".st2{fill:none;stroke:#0000FF;stroke-width:0.25;stroke-opacity:0.5}\n"
        ".st3{fill:none;stroke:#FF0000;stroke-miterlimit:10;}"
    )
    body = '<line class="st2" x1="0" y1="50" x2="100" y2="50"/><path class="st3" d="M50 0 L50 50"/>'
    cp = read_svg(write(tmp_path, style, body))
    assert letters(cp) == ["M", "V", "V"]
    valley = cp.assignments == "V"
    assert np.allclose(cp.fold_angles[valley], 90.0)  # stroke-opacity 0.5 of 180 deg
    assert not cp.notes or all(n.severity != "warning" for n in cp.notes)


@pytest.mark.parametrize(
    "style, attrs, expected",
    [
        # an id rule outranks a class rule, whatever their order
        ("#a{stroke:red} .c{stroke:blue}", 'id="a" class="c"', "M"),
        # between equal selectors the later wins
        (".c{stroke:red} .c{stroke:blue}", 'class="c"', "V"),
        # the style attribute outranks the sheet; !important outranks the style attribute
        (".c{stroke:red}", 'class="c" style="stroke:blue"', "V"),
        (".c{stroke:red !important}", 'class="c" style="stroke:blue"', "M"),
        # the sheet outranks a presentation attribute
        (".c{stroke:red}", 'class="c" stroke="blue"', "M"),
        # type and descendant selectors, as CSS matches them
        ("g line{stroke:blue}", "", "V"),
    ],
)
def test_the_cascade_decides_the_colour(tmp_path, style, attrs, expected):
    body = f'<g><line {attrs} x1="0" y1="50" x2="100" y2="50"/></g>'
    cp = read_svg(write(tmp_path, ".edge{stroke:black}" + style, body))
    assert letters(cp) == [expected]


def test_a_group_rule_is_inherited(tmp_path):
    body = '<g class="valleys"><line x1="0" y1="50" x2="100" y2="50"/></g>'
    cp = read_svg(write(tmp_path, ".edge{stroke:black} .valleys{stroke:#00f}", body))
    assert letters(cp) == ["V"]


def test_unreadable_rules_are_left_out_and_named(tmp_path):
    style = ".edge{stroke:black} @media print{.x{stroke:red}} p:::q{stroke:red} .v{stroke:blue}"
    body = '<line class="v" x1="0" y1="50" x2="100" y2="50"/>'
    cp = read_svg(write(tmp_path, style, body))
    assert letters(cp) == ["V"]
    (note,) = [n for n in cp.notes if n.code == "style-rule"]
    assert note.severity == "warning" and "@media" in note.message and "p:::q" in note.message


def test_a_sheet_colour_outside_the_convention_names_the_element(tmp_path):
    body = '<line id="odd" class="o" x1="0" y1="50" x2="100" y2="50"/>'
    with pytest.raises(Exception, match=r"<line id=odd>.*stroke #123456"):
        read_pattern(write(tmp_path, ".edge{stroke:black} .o{stroke:#123456}", body))


def test_a_sheet_too_costly_to_match_is_refused_naming_the_file(tmp_path, monkeypatch):
    """Rules with combinators over a deep, large document cost elements x depth steps each:
    past the budget the file is refused at once (a hostile one would take minutes)."""
    from origami_cad.pattern.formats import svgcss

    monkeypatch.setattr(svgcss, "MATCH_BUDGET", 100)
    deep = "<g>" * 20 + '<line x1="0" y1="50" x2="100" y2="50"/>' * 10 + "</g>" * 20
    path = write(tmp_path, ".edge{stroke:black} g line{stroke:blue}", deep, "deep.svg")
    with pytest.raises(Exception, match=r"deep\.svg: its <style> has 1 rule\(s\) with combinators"):
        read_svg(path)
    # the same rules as classes cost nothing extra, and read
    flat = write(
        tmp_path, ".edge{stroke:black} .v{stroke:blue}", deep.replace("<line", '<line class="v"')
    )
    assert letters(read_svg(flat)) == ["V"]
