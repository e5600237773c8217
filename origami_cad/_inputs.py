"""Which files no output may replace: the command's inputs and the files they name.

Part of the safe file output of :mod:`origami_cad._fileio` (the rules are in
``docs/outputs.md``): :func:`check_outputs` refuses, before any work, an output that
resolves to an input or to a file an input names (:func:`referenced_files`).
"""

from __future__ import annotations

import contextlib
import os
import stat
from collections.abc import Iterator, Sequence
from pathlib import Path

from origami_cad.errors import OutputError

__all__ = [
    "MAX_REFERENCED",
    "MAX_SEARCHED",
    "check_outputs",
    "protected_files",
    "protection",
    "referenced_files",
    "refuse_broken_link",
]

PathLike = str | os.PathLike[str]


def _real(path: PathLike) -> Path:
    return Path(os.path.realpath(os.path.abspath(path)))


def _broken_link(path: PathLike) -> Path | None:
    """The first link along ``path`` (the path itself or a folder on the way) that points
    to nothing: writing there would create whatever it points to, wherever that is."""
    probe = Path(os.path.abspath(path))
    for part in (*reversed(probe.parents), probe):
        if os.path.islink(part) and not os.path.exists(part):
            return part
    return None


def refuse_broken_link(path: PathLike, shown: str) -> None:
    """An :class:`OutputError` when a link along ``path`` points to nothing (``shown``: how
    the message names the output)."""
    link = _broken_link(path)
    if link is not None:
        which = "" if link == Path(os.path.abspath(path)) else f"{link} "
        raise OutputError(
            f"{shown}: {which}is a symbolic link to {os.readlink(link)}, which does not "
            "exist; remove the link or choose another output"
        )


def referenced_files(inputs: Sequence[PathLike]) -> dict[Path, tuple[PathLike, str]]:
    """The files the input files name, found transitively: ``{file: (input, key)}``.

    A TOML input names a file by any string value that resolves, relative to its
    folder, to an existing file (a design's ``[pattern] path``, a robot's pattern and
    routes, a sequence's ``mapping``); a named TOML file is searched in turn. The
    inputs themselves are not listed. Unreadable inputs are skipped (their reader
    reports them).
    """
    found: dict[Path, tuple[PathLike, str]] = {}
    seen = {_real(p) for p in inputs}
    todo = [(Path(p), p) for p in inputs]
    while todo and len(seen) < MAX_REFERENCED:
        path, shown = todo.pop()
        for key, target in _named_files(path):
            if target in seen:
                continue
            seen.add(target)
            found[target] = (shown, key)
            if target.suffix.lower() == ".toml":
                todo.append((target, target))
    return found


#: Most files :func:`referenced_files` follows.
MAX_REFERENCED = 1000
#: Largest TOML file searched for file names, bytes.
MAX_SEARCHED = 10_000_000


def _named_files(path: Path) -> Iterator[tuple[str, Path]]:
    """``(key, file)`` for each string value of a TOML file that names an existing file."""
    import tomllib

    if path.suffix.lower() != ".toml":
        return
    try:
        st = os.stat(path)
        if not stat.S_ISREG(st.st_mode) or st.st_size > MAX_SEARCHED:
            return  # a FIFO or a device would block, or never end: its reader refuses it
        data = tomllib.loads(Path(path).read_text(encoding="utf-8"))
    except (OSError, ValueError, RecursionError):
        return
    base = _real(path).parent
    stack: list[tuple[str, object]] = [("", data)]
    while stack:
        key, value = stack.pop()
        if isinstance(value, dict):
            stack += [(f"{key}.{k}" if key else str(k), v) for k, v in value.items()]
        elif isinstance(value, list):
            stack += [(f"{key}[{i}]", v) for i, v in enumerate(value)]
        elif isinstance(value, str) and 0 < len(value) < 4096 and "\0" not in value:
            with contextlib.suppress(OSError, ValueError):
                target = _real(base / value)
                if target.is_file():
                    yield key, target


def protected_files(inputs: Sequence[PathLike]) -> dict[Path, str]:
    """Every file no output may replace, with the end of the sentence refusing it."""
    protected = {
        ref: f"would overwrite {ref}, which the input {src} names (key '{key}'); "
        "choose another output"
        for ref, (src, key) in referenced_files(inputs).items()
    }
    protected |= {_real(p): "would overwrite the input" for p in inputs}
    return protected


def protection(path: PathLike, protected: dict[Path, str]) -> str | None:
    """Why ``path`` may not be an output (the end of the sentence refusing it), or None.

    ``protected`` is :func:`protected_files`'s. The file is found by its resolved path,
    or, for a hard link (another name of the same file), by its device and inode.
    """
    real = _real(path)
    if real in protected:
        return protected[real]
    try:
        st = os.stat(real)
    except OSError:
        return None
    if st.st_nlink < 2:
        return None
    for other, why in protected.items():
        with contextlib.suppress(OSError):
            if os.path.samestat(st, os.stat(other)):
                link = f"is a hard link to {other}: it would overwrite"
                return why.replace("would overwrite", link, 1)
    return None


def check_outputs(
    inputs: Sequence[PathLike] = (),
    files: Sequence[PathLike] = (),
    folders: Sequence[PathLike] = (),
) -> None:
    """Refuse outputs that would destroy an input or cannot be written, before any work.

    Parameters
    ----------
    inputs : sequence of path-like
        Files the command reads; the files they name (:func:`referenced_files`) are
        protected too.
    files : sequence of path-like
        Files the command writes.
    folders : sequence of path-like
        Folders the command writes into.

    Raises
    ------
    OutputError
        An output resolves to an input or a file an input names, two outputs are
        the same file, a file output is an existing folder, a folder output is an
        existing file, a parent of an output is a file, or a symbolic link along an
        output points to nothing.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> (d / "d.toml").write_text("x = 1")
    5
    >>> check_outputs([d / "d.toml"], files=[d / "d.png"])
    >>> check_outputs([d / "d.toml"], files=[d / "d.toml"])
    Traceback (most recent call last):
    ...
    origami_cad.errors.OutputError: ...d.toml: the output would overwrite the input
    """
    protected = protected_files(inputs)
    seen: dict[Path, PathLike] = {}
    for out in list(folders) + list(files):  # a folder's link first: its files are in it
        refuse_broken_link(out, str(out))
    for out in list(files) + list(folders):
        real, why = _real(out), protection(out, protected)
        if why is not None:
            raise OutputError(f"{out}: the output {why}")
        if real in seen:
            raise OutputError(f"{out}: given twice as an output")
        seen[real] = out
        probe = real.parent
        while not probe.exists():
            probe = probe.parent
        if not probe.is_dir():
            raise OutputError(f"{out}: {probe} is a file, not a folder")
    for out in files:
        if _real(out).is_dir():
            raise OutputError(f"{out}: is a folder; give a file name")
    for out in folders:
        real = _real(out)
        if real.exists() and not real.is_dir():
            raise OutputError(f"{out}: exists and is not a folder; give a folder for the outputs")
