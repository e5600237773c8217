"""What a command returns (:class:`Outputs`) and the helpers its outputs share."""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from origami_cad._inputs import refuse_broken_link
from origami_cad.errors import OptionsError, OutputError

__all__ = [
    "FOLDER_HELP",
    "Outputs",
    "check_suffix",
    "file_format",
    "moved",
    "one_output",
    "sources",
    "staged",
    "wrote",
]

PathLike = str | os.PathLike[str]


@dataclass
class Outputs:
    """What a command wrote and what it found.

    Attributes
    ----------
    files : list of Path
        Every file written, in order.
    images : list of (Path, str)
        The pictures among them (.png, .gif, and .glb 3D views), with a caption.
    numbers : list of (str, str)
        Key results, name and value with its unit.
    messages : list of str
        Lines for the user: summary and warnings.
    warnings : list of str
        Warnings the command line prints on stderr (``origami-cad: warning: ...``): a
        result the library returned but could not fully confirm.
    result : object
        The library result the files were made from (a ``DCQCResult``,
        ``Fabrication``, list of ``ArmDesign``...), or ``None``.
    status : int
        0, or 1 when the command ran but its answer is negative (a pattern with
        errors, a routing that never folds).
    """

    files: list[Path] = field(default_factory=list)
    images: list[tuple[Path, str]] = field(default_factory=list)
    numbers: list[tuple[str, str]] = field(default_factory=list)
    messages: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    result: Any = None
    status: int = 0

    def extend(self, other: Outputs) -> Outputs:
        """Add another command's outputs to these (for chained commands); returns ``self``.

        A number two commands both report (the same name and value: a pattern's size,
        read by each) is kept once.
        """
        self.files += other.files
        self.images += other.images
        self.numbers += [n for n in other.numbers if n not in self.numbers]
        self.messages += other.messages
        self.warnings += other.warnings
        return self


def _is_stream(path: PathLike) -> bool:
    """A device or pipe (``/dev/stdout``, a FIFO): written into, whatever its name."""
    import stat

    try:
        mode = os.stat(path).st_mode
    except OSError:
        return False
    return stat.S_ISCHR(mode) or stat.S_ISFIFO(mode)


def check_suffix(path: PathLike, allowed: Sequence[str], what: str) -> None:
    """Refuse an output file whose extension is not one of ``allowed`` (``OptionsError``)."""
    if _is_stream(path):
        return  # a device or pipe needs no extension: it takes the first format
    refuse_broken_link(path, str(path))  # its name is not the file's it would create
    if os.path.isdir(path):
        raise OutputError(f"{path}: is a folder; give a file name")
    if Path(os.path.realpath(path)).suffix.lower() not in allowed:  # a link: its file's name
        raise OptionsError(f"{path}: {what} is written as {', '.join(allowed)} (by its extension)")


def file_format(path: PathLike, allowed: Sequence[str]) -> str:
    """The format an output is written in: its extension (lower case), or for a device or
    pipe (``/dev/stdout``, a FIFO), whose name has none, the first of ``allowed``.

    >>> file_format("a/b.SVG", (".fold", ".svg")), file_format("/dev/null", (".fold", ".svg"))
    ('.svg', '.fold')
    """
    if _is_stream(path):
        return allowed[0]
    return Path(os.path.realpath(path)).suffix.lower()


def one_output(command: str, file: bool, given: list) -> Any:
    """The one ``-o`` of a command that writes one file (``file``) or one folder: the
    command line gives every ``-o`` as a list, and a second one is refused, never dropped."""
    if len(given) == 1:
        return given[0]
    what, repeated = "one file" if file else "one folder", " -o ".join(map(str, given))
    raise OptionsError(
        f"-o: {command} writes {what}, got {len(given)} (-o {repeated}); "
        "only pattern and fold write each -o given"
    )


def sources(*items: Any) -> list:
    """Input paths, and the file a design was read from, that no output may replace."""
    return [s for s in (getattr(i, "source", i) for i in items) if s is not None]


def moved(files: Sequence[Path], stage: Path, folder: PathLike) -> list[Path]:
    """Where the files written into ``stage`` are once in ``folder``."""
    return [Path(folder) / Path(f).relative_to(stage) for f in files]


def staged(stage: Path) -> list[Path]:
    """The files written into ``stage`` (sorted), not the skeleton's own."""
    return sorted(p for p in stage.iterdir() if not p.name.startswith("."))


def wrote(where: PathLike, names: Sequence[Any] | None = None, detail: str = "") -> str:
    """The line saying what a command wrote: ``wrote FOLDER/: a b c`` (the ``names`` of
    the files written into the folder ``where``), or ``wrote FILE`` (one file), followed
    by `` (detail)`` when given.

    >>> wrote("fab", ["a/x.stl", "y.json"]), wrote("cp.fold", detail="2 panels")
    ('wrote fab/: x.stl y.json', 'wrote cp.fold (2 panels)')
    """
    line = (
        f"wrote {where}"
        if names is None
        else f"wrote {where}/: " + " ".join(Path(n).name for n in names)
    )
    return f"{line} ({detail})" if detail else line


#: The help of ``-o`` of a command writing a folder.
FOLDER_HELP = "output folder; only this command's files are written into it, all else is kept"
