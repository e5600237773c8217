"""XML read within limits, for the XML crease-pattern formats (SVG, ORIPA's ``.opx``).

:func:`parse_bounded` parses incrementally and stops, with a PatternError naming the file
and the element, at an element nested deeper than its depth limit or past its element
limit, so a hostile file costs neither the stack nor the memory. Python's expat resolves
no external entity and bounds entity expansion (expat >= 2.4); a format that never holds a
document type declaration can refuse one outright (``declarations=False``).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

from origami_cad._toml import printable
from origami_cad.errors import PatternError

__all__ = ["local_name", "parse_bounded"]


def local_name(tag: str) -> str:
    """An element's tag without its namespace (``{http://...}svg`` -> ``svg``)."""
    return tag.rsplit("}", 1)[-1]


def _refuse_declarations(p: Path, name: str) -> None:
    """PatternError when the file declares a document type or entities."""
    tail = b""
    with open(p, "rb") as fh:
        while chunk := fh.read(1 << 20):
            window = (tail + chunk).upper()
            if b"<!DOCTYPE" in window or b"<!ENTITY" in window:
                raise PatternError(
                    f"{name}: declares a document type or entities (<!DOCTYPE, <!ENTITY), "
                    "which this format never holds; refused (entity expansion)"
                )
            tail = chunk[-16:]


def parse_bounded(
    p: Path,
    name: str,
    max_depth: int,
    max_elements: int,
    why_depth: str = "",
    declarations: bool = True,
) -> ET.Element:
    """The root element of the XML file ``p`` (``name`` starts every error).

    An element nested deeper than ``max_depth`` (``why_depth`` says why the limit), the
    element past ``max_elements``, malformed XML, an unreadable file and, unless
    ``declarations``, a ``<!DOCTYPE`` or ``<!ENTITY`` are PatternErrors.
    """
    root = None
    depth = count = 0
    try:
        if not declarations:
            _refuse_declarations(p, name)
        with open(p, "rb") as fh:
            for event, el in ET.iterparse(fh, events=("start", "end")):
                if event == "end":
                    depth -= 1
                    continue
                depth, count = depth + 1, count + 1
                root = el if root is None else root
                if depth > max_depth:
                    raise PatternError(
                        f"{name}: <{printable(local_name(el.tag))}> (element {count:,}) is "
                        f"nested {depth} deep, deeper than the limit of {max_depth}{why_depth}"
                    )
                if count > max_elements:
                    raise PatternError(f"{name}: more than {max_elements:,} elements")
    except ET.ParseError as exc:
        raise PatternError(f"{name}: not valid XML ({exc})") from None
    except OSError as exc:
        raise PatternError(f"{name}: cannot be read ({exc.strerror or exc})") from None
    assert root is not None  # a document has a root, or iterparse raised ParseError
    return root
