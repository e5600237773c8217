"""Safe file output shared by every writer of the package.

The rules, documented for users in ``docs/outputs.md``:

* A writer never leaves a half-written file: it writes a temporary file beside
  the target and renames it over the target only when complete.
* A writer never replaces anything but a regular file. A symbolic link is
  written through (the file it points to is replaced, the link stays); a
  device or pipe (``/dev/stdout``, a FIFO) is written into once the output is
  complete; a folder given where a file is expected is an error.
* A command that writes a folder writes *only its own files* into it. Whatever
  else the folder holds (the user's design, notes, sub-folders) is left
  untouched; a new folder that ends up unused is removed again.
* No output may resolve to one of the command's inputs
  (:func:`check_outputs`, and again when the files are put in place).
* An interrupt (Ctrl-C, SIGTERM) noted within :func:`handle_signals` is
  honoured when the output would be put in place, even where a library swallowed
  the ``KeyboardInterrupt``: nothing is written and the temporary files go.
"""

from __future__ import annotations

import contextlib
import errno
import os
import shutil
import signal
import stat
import sys
import tempfile
import threading
from collections.abc import Callable, Iterable, Iterator, Sequence
from pathlib import Path
from typing import IO

from origami_cad.errors import OutputError

__all__ = [
    "Interrupted",
    "atomic_directory",
    "atomic_path",
    "atomic_write",
    "check_outputs",
    "handle_signals",
    "interrupted",
]

PathLike = str | os.PathLike[str]


class Interrupted(KeyboardInterrupt):
    """Raised by the signal handlers for SIGINT and SIGTERM; ``signum`` says which."""

    def __init__(self, signum: int) -> None:
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


_received: list[int] = []


def interrupted() -> int | None:
    """The number of the first interrupting signal received since the handlers were installed."""
    return _received[0] if _received else None


def _in_import(frame) -> bool:
    while frame is not None:
        if frame.f_code.co_filename.startswith("<frozen importlib"):
            return True
        frame = frame.f_back
    return False


def _on_signal(signum: int, frame) -> None:
    if _in_import(frame):
        # an exception inside a module's import can crash an extension module's
        # initialisation (VTK segfaults): deliver the signal again once it is done
        threading.Timer(0.05, os.kill, (os.getpid(), signum)).start()
        return
    first = not _received
    _received.append(signum)
    if first:  # a second signal must not cut short the clean-up the first one started
        sys.unraisablehook = _quiet_unraisable
        raise Interrupted(signum)


def _quiet_unraisable(unraisable) -> None:
    """After an interrupt, say nothing of errors in ``__del__`` (no traceback on stderr).

    The interrupt may have cut an object short in its constructor (a pyvista
    ``Renderer`` during a render), whose ``__del__`` then fails when the process
    exits; the command has already said it was interrupted and wrote nothing.
    """


@contextlib.contextmanager
def handle_signals() -> Iterator[None]:
    """Within the block, SIGINT and SIGTERM raise :class:`Interrupted` and are remembered.

    Used by the command-line tool (main thread only). The remembered signal
    makes every pending atomic output refuse to complete, so an interrupt that a
    library swallowed (a VTK callback, a worker loop) still leaves nothing behind.
    The previous handlers are restored and the memory cleared on leaving.
    """
    _received.clear()
    previous = {sig: signal.signal(sig, _on_signal) for sig in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        _received.clear()


def _raise_if_interrupted() -> None:
    if _received:
        raise Interrupted(_received[0])


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _describe(mode: int) -> str:
    if stat.S_ISDIR(mode):
        return "a folder"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    if stat.S_ISFIFO(mode):
        return "a pipe"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "not a regular file"


def _real(path: PathLike) -> Path:
    return Path(os.path.realpath(os.path.abspath(path)))


def _ensure_folder(folder: Path, shown: PathLike) -> list[Path]:
    """Create ``folder`` and its missing parents; return those created, outermost first."""
    missing = []
    probe = folder
    while not probe.exists():
        if probe.is_symlink():
            raise OutputError(f"{shown}: {probe} is a broken symbolic link")
        missing.append(probe)
        probe = probe.parent
    if not probe.is_dir():
        raise OutputError(f"{shown}: {probe} is a file, not a folder")
    for p in reversed(missing):
        try:
            p.mkdir()
        except FileExistsError:
            pass
        except OSError as exc:
            raise OutputError(f"{shown}: cannot create folder {p}: {exc.strerror}") from None
    return list(reversed(missing))


def _remove_created(created: Iterable[Path]) -> None:
    for p in reversed(list(created)):
        with contextlib.suppress(OSError):
            p.rmdir()  # only if still empty


def _temp_file(folder: Path, suffix: str) -> Path:
    # short prefix and suffix: a target name near the file-system limit must not
    # make the temporary name too long
    fd, tmp = tempfile.mkstemp(prefix=".oc-", suffix=suffix[-16:], dir=folder)
    os.close(fd)
    return Path(tmp)


def _target(path: PathLike) -> tuple[Path, os.stat_result | None]:
    """The file to write for ``path`` (links followed) and its status if it exists."""
    try:
        st = os.stat(path)  # follows links
    except FileNotFoundError:
        return _real(path), None
    except OSError as exc:
        raise OutputError(f"{path}: {exc.strerror}") from None
    if stat.S_ISDIR(st.st_mode):
        raise OutputError(f"{path}: is a folder; give a file name")
    if not stat.S_ISREG(st.st_mode):  # a device or pipe, maybe behind /proc/self/fd links
        return Path(path), st
    return _real(path), st


def _install(src: Path, dest: Path, st: os.stat_result | None) -> None:
    """Put the finished file ``src`` in place of ``dest`` (already resolved)."""
    if st is not None and not stat.S_ISREG(st.st_mode):
        # a device or pipe: write into it, never rename over it
        with open(src, "rb") as fin, open(dest, "wb") as fout:
            shutil.copyfileobj(fin, fout)
        src.unlink()
        return
    os.chmod(src, 0o666 & ~_umask())  # mkstemp makes 0600; give the usual mode
    try:
        os.replace(src, dest)
    except OSError as exc:
        if exc.errno != errno.EXDEV:
            raise
        tmp = _temp_file(dest.parent, dest.suffix)  # another file system: copy beside, rename
        try:
            shutil.copyfile(src, tmp)
            os.chmod(tmp, 0o666 & ~_umask())
            os.replace(tmp, dest)
        except BaseException:
            tmp.unlink(missing_ok=True)
            raise
        src.unlink()


def _user_paths(exc: BaseException, staged: Path, shown: PathLike) -> None:
    """Say ``shown`` (the user's path) wherever ``exc`` names ``staged`` (our temporary one).

    A check run on a staged file (a sequence read back, a 3MF validated) raises with the
    temporary file's name, which is gone once the error is printed; the user must read
    the path they gave. The message, its notes and an ``OSError``'s file names are
    rewritten in place.
    """
    shown = str(shown).rstrip(os.sep) or str(shown)
    names = {str(staged): shown}
    real = os.path.realpath(staged)
    names.setdefault(real, shown)

    def fix(text):
        if not isinstance(text, str):
            return text
        for old, new in names.items():
            text = text.replace(old, new)
        return text

    exc.args = tuple(fix(a) for a in exc.args)
    if isinstance(exc, OSError):
        exc.filename, exc.filename2 = fix(exc.filename), fix(exc.filename2)
    notes = getattr(exc, "__notes__", None)
    if isinstance(notes, list):
        notes[:] = [fix(n) for n in notes]


def _make_temp(make: Callable[[], Path], created: list[Path], where: str) -> Path:
    """``make()``: a temporary file or folder; if that fails, the folders ``created``
    for it are removed and :class:`OutputError` says ``where: why``."""
    try:
        return make()
    except OSError as exc:
        _remove_created(created)
        raise OutputError(f"{where}: {exc.strerror}") from None


@contextlib.contextmanager
def atomic_path(path: PathLike) -> Iterator[Path]:
    """Yield a temporary path; on success its file replaces ``path``.

    Use it for libraries that insist on writing a file themselves (ezdxf,
    matplotlib, build123d). On an exception, or after an interrupt, the
    temporary file is removed and ``path`` is left untouched. A link at ``path``
    is written through; a device or pipe is written into; a folder is refused.

    Raises
    ------
    OutputError
        ``path`` is a folder, or its parent cannot be a folder.
    """
    dest, st = _target(path)
    created = _ensure_folder(dest.parent, path)
    if st is not None and not stat.S_ISREG(st.st_mode):
        tmp_dir = Path(tempfile.gettempdir())  # a device's folder (/dev) is no place for it
    else:
        tmp_dir = dest.parent
    tmp = _make_temp(
        lambda: _temp_file(tmp_dir, Path(path).suffix or ".tmp"),
        created,
        f"{path}: cannot write in {tmp_dir}",
    )
    try:
        yield tmp
        _raise_if_interrupted()
        _install(tmp, dest, st)
    except BaseException as exc:
        tmp.unlink(missing_ok=True)
        _remove_created(created)
        _user_paths(exc, tmp, path)
        raise


@contextlib.contextmanager
def atomic_write(path: PathLike, mode: str = "w", **kwargs) -> Iterator[IO]:
    """Open a temporary file for writing; it replaces ``path`` only on success."""
    with atomic_path(path) as tmp, open(tmp, mode, **kwargs) as fh:
        yield fh


def _staged_files(stage: Path) -> list[Path]:
    return sorted(p.relative_to(stage) for p in stage.rglob("*") if not p.is_dir())


@contextlib.contextmanager
def atomic_directory(path: PathLike, inputs: Sequence[PathLike] = ()) -> Iterator[Path]:
    """Yield a temporary folder; on success its files are put into ``path``.

    For commands that write several files. Only the command's own files are
    written into ``path``: every other file or folder already there is kept.
    Each file is complete when it appears. On an exception (or an interrupt)
    nothing is written, and a folder created for the output is removed again.

    Parameters
    ----------
    path : path-like
        The output folder; created if missing. A link to a folder is followed.
    inputs : sequence of path-like
        The command's input files: an output file that resolves to one of them
        is an error (checked before anything is put in place).

    Raises
    ------
    OutputError
        ``path`` exists and is not a folder, an output would replace an input,
        a folder or a non-regular file.
    """
    shown = path
    folder = _real(path)
    if folder.exists() and not folder.is_dir():
        raise OutputError(f"{shown}: exists and is not a folder; give a folder for the outputs")
    created = _ensure_folder(folder, shown)
    stage = _make_temp(
        lambda: Path(tempfile.mkdtemp(prefix=".oc-", dir=folder)),
        created,
        f"{shown}: cannot write in this folder",
    )
    try:
        yield stage
        _raise_if_interrupted()
        plan = _plan_install(stage, folder, shown, inputs)
        for rel, dest, st in plan:
            _ensure_folder(dest.parent, shown)
            _install(stage / rel, dest, st)
    except BaseException as exc:
        shutil.rmtree(stage, ignore_errors=True)
        _remove_created(created)
        _user_paths(exc, stage, shown)
        raise
    shutil.rmtree(stage, ignore_errors=True)


def _plan_install(stage: Path, folder: Path, shown: PathLike, inputs: Sequence[PathLike]):
    """Where each staged file goes; every check done before anything moves."""
    protected = {_real(p) for p in inputs}
    plan = []
    for rel in _staged_files(stage):
        out = folder / rel
        try:
            dest, st = _target(out)
        except OutputError:
            raise OutputError(
                f"{shown}: {rel.as_posix()} is a folder there; the output file cannot replace it"
            ) from None
        if dest in protected:
            raise OutputError(
                f"{shown}: the output {rel.as_posix()} would overwrite the input {dest}; "
                "choose another output folder"
            )
        plan.append((rel, dest, st))
    return plan


def check_outputs(
    inputs: Sequence[PathLike] = (),
    files: Sequence[PathLike] = (),
    folders: Sequence[PathLike] = (),
) -> None:
    """Refuse outputs that would destroy an input or cannot be written, before any work.

    Parameters
    ----------
    inputs : sequence of path-like
        Files the command reads.
    files : sequence of path-like
        Files the command writes.
    folders : sequence of path-like
        Folders the command writes into.

    Raises
    ------
    OutputError
        An output resolves to an input, two outputs are the same file, a file
        output is an existing folder, a folder output is an existing file, or a
        parent of an output is a file.

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
    protected = {_real(p): p for p in inputs}
    seen: dict[Path, PathLike] = {}
    for out in list(files) + list(folders):
        real = _real(out)
        if real in protected:
            raise OutputError(f"{out}: the output would overwrite the input")
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
