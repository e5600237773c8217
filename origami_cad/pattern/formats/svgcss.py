"""SVG style sheets: the ``<style>`` rules that colour a drawing's crease lines.

Illustrator's default SVG export ("Styling: Style Elements") writes no colour on the lines
themselves: each ``<path class="st2">`` takes its stroke from a rule such as
``.st2{fill:none;stroke:#0000FF;}`` in a ``<style>`` element, as a browser (and so Origami
Simulator) applies it. :func:`style_sheet` reads every ``<style>`` of a document with
tinycss2 and matches its selectors with cssselect2 (CSS Selectors level 3, the parsers
CairoSVG uses), and gives each element the declarations that apply to it, in the cascade's
order: by specificity, then by the order of the rules. A rule the parsers cannot read
(a malformed selector, an unsupported at-rule) is left out, as a browser leaves it out,
and named in a note.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET

import cssselect2
import tinycss2

from origami_cad.errors import PatternError
from origami_cad.pattern.model import printable

__all__ = ["MATCH_BUDGET", "StyleSheet", "style_sheet"]

#: The most ancestor steps the rules with combinators (``g line``, ``g > line``) may cost:
#: their number times the elements times the document's depth. Illustrator's sheets have
#: none; a file past this (a hostile one: 1,000,000 elements 256 deep) is refused, not
#: matched for minutes.
MATCH_BUDGET = 20_000_000


class StyleSheet:
    """The style rules of one document, matched to its elements.

    Attributes
    ----------
    normal, important : dict
        ``id(element)`` -> ``{property: value}``: the declarations of the matching rules
        without and with ``!important``, the later winning.
    skipped : list of str
        The rules left out, each as ``selector``: what could not be read.
    """

    def __init__(self) -> None:
        self.normal: dict[int, dict[str, str]] = {}
        self.important: dict[int, dict[str, str]] = {}
        self.skipped: list[str] = []

    def apply(self, el: ET.Element, attributes: dict[str, str], inline: dict[str, str]):
        """``el``'s properties in the cascade's order: presentation attributes, the
        sheet's rules, the ``style`` attribute, the sheet's ``!important`` rules."""
        key = id(el)
        return {
            **attributes,
            **self.normal.get(key, {}),
            **inline,
            **self.important.get(key, {}),
        }


def _declarations(content) -> list[tuple[str, str, bool]]:
    """``(name, value, important)`` of a rule's declarations (tinycss2 tokens)."""
    out = []
    for d in tinycss2.parse_blocks_contents(content, skip_comments=True, skip_whitespace=True):
        if d.type == "declaration":
            out.append((d.lower_name, tinycss2.serialize(d.value).strip(), bool(d.important)))
    return out


def _matcher(root: ET.Element, skipped: list[str]) -> tuple[cssselect2.Matcher | None, int]:
    """A cssselect2 matcher holding every readable rule of the ``<style>`` elements below
    ``root`` (None when there is none) and how many of them have a combinator.
    Unreadable rules go to ``skipped``."""
    matcher = cssselect2.Matcher()
    rules = combined = 0
    for el in root.iter():
        if not isinstance(el.tag, str) or el.tag.rsplit("}", 1)[-1] != "style":
            continue
        if el.attrib.get("type", "text/css").strip().lower() not in ("text/css", ""):
            continue
        text = "".join(el.itertext())
        for rule in tinycss2.parse_stylesheet(text, skip_comments=True, skip_whitespace=True):
            if rule.type != "qualified-rule":
                what = f"@{rule.at_keyword}" if rule.type == "at-rule" else rule.type
                skipped.append(printable(what, 40))
                continue
            try:
                selectors = cssselect2.compile_selector_list(rule.prelude)
            except cssselect2.SelectorError:
                skipped.append(printable(tinycss2.serialize(rule.prelude).strip(), 40))
                continue
            payload = _declarations(rule.content)
            for selector in selectors:
                matcher.add_selector(selector, payload)
                rules += 1
            text = tinycss2.serialize(rule.prelude).strip()
            combined += len(selectors) if re.search(r"[\s>+~]", text) else 0
    return (matcher if rules else None), combined


def _depth_and_count(root: ET.Element) -> tuple[int, int]:
    """The document's depth and element count (without recursion)."""
    depth, count, stack = 0, 0, [(root, 1)]
    while stack:
        el, d = stack.pop()
        depth, count = max(depth, d), count + 1
        stack.extend((child, d + 1) for child in el)
    return depth, count


def style_sheet(root: ET.Element, name: str = "") -> StyleSheet:
    """The rules of every ``<style>`` element of the document ``root``, matched to its
    elements (an empty sheet when it has none).

    Raises
    ------
    PatternError
        Naming the file (``name``) when matching its rules with combinators would cost
        more than :data:`MATCH_BUDGET` steps.
    """
    sheet = StyleSheet()
    matcher, combined = _matcher(root, sheet.skipped)
    if matcher is None:
        return sheet
    if combined:
        depth, count = _depth_and_count(root)
        if combined * depth * count > MATCH_BUDGET:
            raise PatternError(
                f"{name}: its <style> has {combined} rule(s) with combinators (such as "
                f"'g line') over {count:,} elements {depth} deep: too costly to match "
                "(use class selectors, as Illustrator writes them)"
            )
    for wrapper in cssselect2.ElementWrapper.from_xml_root(root).iter_subtree():
        matches = matcher.match(wrapper)
        if not matches:
            continue
        normal: dict[str, str] = {}
        important: dict[str, str] = {}
        for _specificity, _order, pseudo, payload in sorted(matches, key=lambda m: m[:2]):
            if pseudo is not None:
                continue  # ::before and the like draw nothing here
            for name, value, is_important in payload:
                (important if is_important else normal)[name] = value
        if normal:
            sheet.normal[id(wrapper.etree_element)] = normal
        if important:
            sheet.important[id(wrapper.etree_element)] = important
    return sheet
