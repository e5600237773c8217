"""Design files (TOML): the input of every command.

.. code-block:: toml

    [pattern]
    kind = "transition-graph"   # or "miura", or "file"
    unit_width = 36.0           # mm, one tessellation unit (two panel rows)
    copies = 3
    entry_flag = 1              # EF_0: 1 valley, 0 mountain
    start = [0.0, 0.0]          # T_s, mm
    fold_ratio = 0.5            # p at which `vectors` are drawn
    vectors = [[40, 0], [30, 25], [30, -10], [40, 15], [30, 0]]  # [mm, deg]
    # or: lengths = [...] (mm) and shape_angles = [...] (deg)
    hypar_base = false
    min_turn = 5.0              # deg, optional
    merge_small_turns = false   # optional

``kind = "miura"`` takes ``rows``, ``columns``, ``panel_length``, ``panel_width``
(mm), ``sector_angle`` (deg) and optionally ``entry_flag``; ``kind = "file"``
takes ``path`` (relative to the design file) of a ``.fold``, ``.dxf`` or ``.svg``
and optionally its size: ``unit`` (``"mm"``, ``"cm"``, ``"m"``, ``"in"``, ...,
replacing the unit the file declares) and/or ``scale`` (a factor), or ``width``
(mm), and ``tolerance`` (mm: vertices closer than this merge), as
:func:`~origami_cad.pattern.io.read_pattern` takes them.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from origami_cad._args import Arg, brief_value, checked
from origami_cad._display import PatternDisplay
from origami_cad._toml import (
    Table,
    finite_toml,
    input_file,
    load_toml,
    printable,
    toml_table,
)
from origami_cad.errors import DesignError, PatternError
from origami_cad.pattern.formats import READERS
from origami_cad.pattern.io import SIZE_CHECKS, read_pattern
from origami_cad.pattern.miura import MAX_PANELS, miura_pattern
from origami_cad.pattern.model import MAX_VERTICES, CreasePattern
from origami_cad.pattern.tg import DEFAULT_MIN_TURN, TGDesign, design_from_vectors, tg_pattern

__all__ = [
    "KINDS",
    "SIZE_OPTIONS",
    "Design",
    "dump_design",
    "load_design",
    "load_pattern_source",
    "miura_design",
    "tg_design",
]

KINDS = ("transition-graph", "miura", "file")


@dataclass(frozen=True)
class Design(PatternDisplay):
    """A loaded design: its crease pattern and, for TG-based kinds, the TG design.

    Attributes
    ----------
    pattern : CreasePattern
        The flat crease pattern, mm.
    tg : TGDesign or None
        The TG tessellation it comes from (folds in closed form), else ``None``.
    kind : str
        ``transition-graph``, ``miura`` or ``file``.
    source : Path or None
        The file it was read from.
    """

    pattern: CreasePattern
    tg: TGDesign | None
    kind: str
    source: Path | None = None

    def __repr__(self) -> str:
        """One line: the kind, the pattern's counts, the TG's size and the source file."""
        tg = ""
        if self.tg is not None:
            tg = f", TG of {len(self.tg.lengths)} vectors x {self.tg.copies} copies"
        source = f", from {self.source.name!r}" if self.source is not None else ""
        return f"<Design {self.kind}: {self.pattern!r}{tg}{source}>"


@checked(
    PatternError,
    rows=Arg("int", min=1, max=100_000, optional=False),
    columns=Arg("int", min=1, max=100_000, optional=False),
    panel_length=Arg(min=0.0, open_min=True, max=1e9, optional=False),
    panel_width=Arg(min=0.0, open_min=True, max=1e9, optional=False),
    sector_angle=Arg(min=0.0, open_min=True, max=90.0, optional=False),
    entry_flag=Arg("int", choices=(0, 1), optional=False),
)
def miura_design(
    rows: int,
    columns: int,
    panel_length: float,
    panel_width: float,
    sector_angle: float,
    entry_flag: int = 1,
) -> Design:
    """A classic Miura-ori as a :class:`Design` (with its TG when ``rows`` is even)."""
    cp = miura_pattern(rows, columns, panel_length, panel_width, sector_angle, entry_flag)
    tg = None
    if rows % 2 == 0:
        tg = TGDesign(
            (panel_length,) * columns,
            (sector_angle,) * (columns - 1),
            entry_flag,
            2.0 * panel_width,
            rows // 2,
            start=(0.0, panel_width),
        )
    return Design(cp, tg, "miura")


#: the size options of an imported pattern (keywords of read_pattern), and its tolerance
SIZE_OPTIONS = ("unit", "scale", "width", "tolerance")


def _sized(size: dict[str, Any], where: str, kind: str) -> None:
    """A DesignError when size options are given for a design that is not imported."""
    given = [k for k in SIZE_OPTIONS if size.get(k) is not None]
    if given == ["tolerance"] and kind != "file":
        raise DesignError(
            f"{where}: the tolerance option joins up only imported patterns (.fold, .dxf, "
            f'.svg, .opx, or kind = "file"); a {kind!r} design is exact'
        )
    if given and kind != "file":
        given = [k for k in given if k != "tolerance"]
        raise DesignError(
            f"{where}: the {'/'.join(given)} "
            f"{'options size' if len(given) > 1 else 'option sizes'} only "
            f'imported patterns (.fold, .dxf, .svg, .opx, or kind = "file"); a {kind!r} design '
            "is sized by its own keys"
        )


def _file_size(table: Table, size: dict[str, Any]) -> dict[str, Any]:
    """The size options of a ``kind = "file"`` table; those given by the caller win (the
    size as a whole, the tolerance on its own)."""
    number = {k: table.number(k, low=0, low_open=True) if table.has(k) else None for k in (
        "scale", "width", "tolerance")}  # fmt: skip
    own = {"unit": table.string("unit") if table.has("unit") else None, **number}
    if any(size.get(k) is not None for k in ("unit", "scale", "width")):
        own = {**own, **{k: size.get(k) for k in ("unit", "scale", "width")}}
    if size.get("tolerance") is not None:
        own["tolerance"] = size["tolerance"]
    return own


#: a table of each of the package's other TOML files, and what the file is (a design file
#: has a [pattern] table)
_OTHER_FILES = {
    "robot": "a robot file (origami-cad robot, crawl, design-gait)",
    "arm": "an arm design task (origami-cad design-arm)",
    "route": "a string route file",
    "sequence": "a TSA sequence file (origami-cad drive)",
    "crease": "a materials file (--materials)",
}


def _not_a_design(p: Path, data: dict) -> None:
    """Refuse a TOML file without a [pattern] table, saying what kind of file it is when
    its tables tell."""
    kind = next((what for key, what in _OTHER_FILES.items() if key in data), None)
    said = f": it is {kind}, not a design file" if kind else ""
    raise DesignError(f"{p}: missing key 'pattern'{said}")


@checked(PatternError, **SIZE_CHECKS)
def load_design(
    path: str | os.PathLike[str],
    *,
    unit: str | float | None = None,
    scale: float | None = None,
    width: float | None = None,
    tolerance: float | None = None,
) -> Design:
    """Read a design file (TOML).

    ``unit``, ``scale`` and ``width`` size an imported pattern (``kind =
    "file"``; any of them replaces the table's own), and ``tolerance`` (mm) joins it up,
    as :func:`~origami_cad.pattern.io.read_pattern` takes them.

    Raises
    ------
    DesignError
        Naming the file, the table and the key, for unknown, missing, mistyped
        or out-of-range keys, and for size options of a design that is not
        imported.
    """
    p = Path(path)
    data = load_toml(p)
    top = Table(data, str(p))
    if "pattern" not in data:
        _not_a_design(p, data)
    table = top.table("pattern")
    top.finish()
    kind = table.string("kind", choices=KINDS)
    size = {"unit": unit, "scale": scale, "width": width, "tolerance": tolerance}
    _sized(size, str(p), kind)
    try:
        if kind == "transition-graph":
            design = _tg_design(table)
            table.finish()
            return Design(tg_pattern(design, title=p.stem), design, kind, p)
        if kind == "miura":
            rows = table.integer("rows", low=1, high=MAX_PANELS)
            columns = table.integer("columns", low=1, high=MAX_PANELS)
            if rows * columns > MAX_PANELS:
                raise table.error(
                    "columns",
                    f"rows x columns = {rows * columns:,} panels, more than the limit of "
                    f"{MAX_PANELS:,}",
                )
            if (rows + 1) * (columns + 1) > MAX_VERTICES:
                raise table.error(
                    "columns",
                    f"(rows + 1) x (columns + 1) = {(rows + 1) * (columns + 1):,} vertices, "
                    f"more than the limit of {MAX_VERTICES:,} (MAX_VERTICES)",
                )
            length = table.number("panel_length", low=0, low_open=True)
            width = table.number("panel_width", low=0, low_open=True)
            angle = table.number("sector_angle", low=0, high=90, low_open=True, high_open=True)
            flag = table.integer("entry_flag", 1, low=0, high=1)
            table.finish()
            d = miura_design(rows, columns, length, width, angle, flag)
            return Design(d.pattern.with_metadata(title=p.stem), d.tg, kind, p)
        rel = table.string("path")
        options = _file_size(table, size)
        table.finish()
        shown = printable(rel, 300)
        try:
            target = (p.parent / rel).resolve()
        except (OSError, ValueError, RuntimeError) as exc:
            raise table.error("path", f"{shown!r} cannot be used ({exc})") from None
        if target.suffix.lower() not in READERS:
            raise table.error("path", f"{shown!r} is not a {', '.join(READERS)} file")
        try:
            input_file(target, PatternError)
        except PatternError as exc:
            raise table.error("path", str(exc)) from None
        return Design(read_pattern(target, **options), None, kind, p)
    except PatternError as exc:
        raise DesignError(f"{p}: {exc}") from None


def dump_design(
    design: TGDesign | str | os.PathLike[str], *, header: str = "", digits: int | None = None
) -> str:
    """A design file (TOML text) that :func:`load_design` reads back.

    Parameters
    ----------
    design : TGDesign or path
        A TG tessellation (``kind = "transition-graph"``, its lengths in mm and shape
        angles in degrees), or the path of a pattern file (``kind = "file"``, as
        written: relative to where the design file goes).
    header : str
        Comment lines put first (each starting with ``#``).
    digits : int, optional
        Decimals of the lengths and shape angles (default: exact).

    Examples
    --------
    >>> tg = TGDesign((60.0, 50.0), (70.0,), 1, 36.0, 3)
    >>> import tempfile, pathlib
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "d.toml"
    >>> _ = path.write_text(dump_design(tg))
    >>> load_design(path).tg == tg
    True
    """
    lines = [header.rstrip("\n")] if header else []
    if not isinstance(design, TGDesign):
        path = Path(design).as_posix()
        text = "\n".join([*lines, *toml_table("pattern", {"kind": "file", "path": path})])
        return finite_toml(text + "\n", "the design file", DesignError)
    table = {
        "kind": "transition-graph",
        "unit_width": float(design.unit_width),
        "copies": int(design.copies),
        "entry_flag": int(design.entry_flag),
        "start": [float(v) for v in design.start],
        "lengths": [float(v) for v in design.lengths],
        "shape_angles": [float(v) for v in design.shape_angles],
        "hypar_base": bool(design.hypar_base),
    }
    units = {"unit_width": "mm", "lengths": "mm", "shape_angles": "deg"}
    rounded = {} if digits is None else {"lengths": digits, "shape_angles": digits}
    text = "\n".join([*lines, *toml_table("pattern", table, comments=units, digits=rounded)])
    return finite_toml(text + "\n", "the design file", DesignError)


def _tg_design(table: Table) -> TGDesign:
    unit_width = table.number("unit_width", low=0, low_open=True)
    copies = table.integer("copies", low=1, high=MAX_PANELS // 2)
    flag = table.integer("entry_flag", low=0, high=1)
    start = table.point("start", [0.0, 0.0])
    hypar = table.boolean("hypar_base", False)
    has_vectors = table.has("vectors")
    has_vars = table.has("lengths") or table.has("shape_angles")
    if has_vectors == has_vars:
        raise DesignError(
            f"{table.where}: give either 'vectors' (with 'fold_ratio') or 'lengths' and "
            "'shape_angles', not both or neither"
        )
    listed = table.data.get("vectors" if has_vectors else "lengths")
    n_vectors = len(listed) if isinstance(listed, list) else 0
    if 2 * copies * n_vectors > MAX_PANELS:
        raise table.error(
            "copies",
            f"{copies} copies x 2 rows x {n_vectors} vectors = {2 * copies * n_vectors:,} "
            f"panels, more than the limit of {MAX_PANELS:,}",
        )
    if (2 * copies + 1) * (n_vectors + 1) > MAX_VERTICES:
        raise table.error(
            "copies",
            f"{copies:,} copies of {n_vectors} vectors make {(2 * copies + 1) * (n_vectors + 1):,} "
            f"vertices, more than the limit of {MAX_VERTICES:,} (MAX_VERTICES)",
        )
    if has_vectors:
        p = table.number("fold_ratio", low=0, high=1, low_open=True)
        vectors = table.pairs("vectors")
        for i, (length, _) in enumerate(vectors):
            if not length > 0:
                raise table.error("vectors", f"item {i}: length must be > 0 mm, got {length:g}")
        min_turn = table.number(
            "min_turn", DEFAULT_MIN_TURN, low=0, high=90, low_open=True, high_open=True
        )
        merge = table.boolean("merge_small_turns", False)
        return design_from_vectors(
            vectors,
            p,
            flag,
            unit_width=unit_width,
            copies=copies,
            start=start,
            hypar_base=hypar,
            min_turn=min_turn,
            merge_small_turns=merge,
        )
    lengths = table.numbers("lengths", min_length=1, check=lambda v: v > 0, what="must be > 0 mm")
    n = len(lengths) - 1
    angles = table.numbers(
        "shape_angles",
        length=n,
        check=lambda v: 0 < v < 180,
        what="a shape angle must lie in (0, 180) deg",
    )
    return TGDesign(tuple(lengths), tuple(angles), flag, unit_width, copies, start, hypar)


def load_pattern_source(
    path: str | os.PathLike[str],
    *,
    unit: str | float | None = None,
    scale: float | None = None,
    width: float | None = None,
    tolerance: float | None = None,
) -> Design:
    """A design file (``.toml``) or a pattern file (``.fold``/``.dxf``/``.svg``/``.opx``)
    as a Design.

    ``unit``, ``scale`` and ``width`` size an imported pattern and ``tolerance`` (mm)
    joins it up (see :func:`~origami_cad.pattern.io.read_pattern`).
    """
    p = Path(path)
    size = {"unit": unit, "scale": scale, "width": width, "tolerance": tolerance}
    if p.suffix.lower() == ".toml":
        return load_design(p, **size)
    return Design(read_pattern(p, **size), None, "file", p)


def tg_design(
    vectors: Sequence[Sequence[float]],
    fold_ratio: float,
    entry_flag: int = 1,
    *,
    title: str = "",
    **options: Any,
) -> Design:
    """A TG-based design from transition vectors drawn at ``fold_ratio`` (eq. 1).

    ``vectors`` are ``[length mm, absolute angle deg]``; ``options`` are those of
    :func:`~origami_cad.pattern.tg.design_from_vectors` (``unit_width`` mm, ``copies``,
    ``start`` mm, ``hypar_base``, ``min_turn`` deg, ``merge_small_turns``). The same
    design as a ``kind = "transition-graph"`` file with these keys.
    """
    if not isinstance(title, str):
        raise PatternError(f"tg_design: title: expected text, got {brief_value(title)}")
    tg = design_from_vectors(vectors, fold_ratio, entry_flag, **options)
    return Design(tg_pattern(tg, title=title), tg, "transition-graph")
