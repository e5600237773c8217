"""Safe file output shared by every writer of the package.

The rules, documented for users in ``docs/outputs.md``:

* A writer never leaves a half-written file: it writes a temporary file beside
  the target and renames it over the target only when complete.
* A writer never replaces anything but a regular file. A symbolic link is
  written through (the file it points to is replaced, the link stays), unless it
  points to nothing (it would create a file wherever it points): refused; a
  device or pipe (``/dev/stdout``, a FIFO) is written into once the output is
  complete; a folder given where a file is expected is an error.
* A command that writes a folder writes *only its own files* into it. Whatever
  else the folder holds (the user's design, notes, sub-folders) is left
  untouched; a new folder that ends up unused is removed again.
* No output may resolve to one of the command's inputs
  (:func:`check_outputs`, and again when the files are put in place).
* An interrupt (Ctrl-C, SIGTERM) noted within ``_signals.handle_signals`` is
  honoured when the output would be put in place, even where a library swallowed
  the ``KeyboardInterrupt``: nothing is written and the temporary files go.
"""

from __future__ import annotations

import contextlib
import errno
import hashlib
import json
import os
import re
import shutil
import socket
import stat
import tempfile
from collections.abc import Callable, Iterable, Iterator, Sequence
from pathlib import Path
from typing import IO

from origami_cad._inputs import (
    check_outputs,
    protected_files,
    protection,
    referenced_files,
    refuse_broken_link,
)
from origami_cad._signals import Interrupted, note_written, raise_if_interrupted, signals_held
from origami_cad.errors import OutputError

__all__ = [
    "WRITE_ERRORS",
    "GrowingFile",
    "WriteRefused",
    "atomic_directory",
    "atomic_path",
    "atomic_write",
    "check_outputs",
    "clean_stale",
    "referenced_files",
]

PathLike = str | os.PathLike[str]


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


#: This machine, as the temporary names carry it (a folder may be shared over a network).
_HOST = hashlib.sha1(socket.gethostname().encode("utf-8", "replace")).hexdigest()[:6]
#: A temporary name: ``.oc-HOST-PID-random``, so a later run can tell whether its
#: process is gone (:func:`clean_stale`).
_STALE = re.compile(r"\.oc-([0-9a-f]{6})-([0-9]+)-")


def _prefix() -> str:
    return f".oc-{_HOST}-{os.getpid()}-"


def _temp_file(folder: Path, suffix: str) -> Path:
    # short prefix and suffix: a target name near the file-system limit must not
    # make the temporary name too long
    fd, tmp = tempfile.mkstemp(prefix=_prefix(), suffix=suffix[-16:], dir=folder)
    os.close(fd)
    return Path(tmp)


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OverflowError):
        return True  # another user's process (or a number no process can have: keep)
    return True


def clean_stale(folder: PathLike) -> list[Path]:
    """Remove the temporary files and staging folders that killed runs left in ``folder``.

    Only names this package makes (``.oc-HOST-PID-...``), made on this machine by a
    process that no longer runs (``kill -9``, a power cut). A staging folder caught
    while putting its files in place is rolled back first (its journal), so the
    outputs are all the old ones. Returns what was removed.
    """
    removed = []
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return removed
    # staging folders first: their journals need the old files kept beside the targets
    entries.sort(key=lambda e: not e.is_dir(follow_symlinks=False))
    for entry in entries:
        m = _STALE.match(entry.name)
        if m is None or m.group(1) != _HOST:
            continue
        pid = int(m.group(2))
        if pid == os.getpid() or _alive(pid):
            continue
        path = Path(entry.path)
        with contextlib.suppress(OSError):
            if entry.is_dir(follow_symlinks=False):
                _recover(path)
                shutil.rmtree(path)
            else:
                path.unlink()
            removed.append(path)
    return removed


def _target(path: PathLike) -> tuple[Path, os.stat_result | None]:
    """The file to write for ``path`` (links followed) and its status if it exists; a
    link to nothing is refused (it would be created wherever the link points)."""
    try:
        st = os.stat(path)  # follows links
    except FileNotFoundError:
        refuse_broken_link(path, str(path))
        return _real(path), None
    except OSError as exc:
        raise OutputError(f"{path}: {exc.strerror}") from None
    if stat.S_ISDIR(st.st_mode):
        raise OutputError(f"{path}: is a folder; give a file name")
    if not stat.S_ISREG(st.st_mode):  # a device or pipe, maybe behind /proc/self/fd links
        return Path(path), st
    return _real(path), st


#: What a file system says when it refuses to store what was written: a full disk, a
#: quota, a file over the size limit, a read-only file system, an I/O error.
WRITE_ERRORS = frozenset({errno.ENOSPC, errno.EDQUOT, errno.EFBIG, errno.EROFS, errno.EIO})


def _sync(path: PathLike, folder: bool = False) -> None:
    """Flush ``path`` (a file, or with ``folder`` a folder's entries) to the disk.

    A folder's flush is best effort: some file systems cannot flush a folder.
    """
    fd = os.open(path, os.O_RDONLY | (os.O_DIRECTORY if folder else 0))
    try:
        os.fsync(fd)
    except OSError:
        if not folder:
            raise
    finally:
        os.close(fd)


def _install(src: Path, dest: Path, st: os.stat_result | None) -> None:
    """Put the finished file ``src`` in place of ``dest`` (already resolved): flushed to
    the disk first, then renamed over it, so ``dest`` is the old file or the whole new one."""
    if st is not None and not stat.S_ISREG(st.st_mode):
        # a device or pipe: write into it, never rename over it
        with open(src, "rb") as fin, open(dest, "wb") as fout:
            shutil.copyfileobj(fin, fout)
        src.unlink()
        return
    os.chmod(src, 0o666 & ~_umask())  # mkstemp makes 0600; give the usual mode
    _sync(src)
    try:
        os.replace(src, dest)
    except OSError as exc:
        if exc.errno != errno.EXDEV:
            raise
        tmp = _temp_file(dest.parent, dest.suffix)  # another file system: copy beside, rename
        try:
            shutil.copyfile(src, tmp)
            os.chmod(tmp, 0o666 & ~_umask())
            _sync(tmp)
            os.replace(tmp, dest)
        except BaseException:
            tmp.unlink(missing_ok=True)
            raise
        src.unlink()
    _sync(dest.parent, folder=True)


class WriteRefused(OutputError):
    """The file system refused to store an output (:data:`WRITE_ERRORS`): ``where``
    (the user's path), ``reason`` (its words) and what was ``kept`` instead."""

    def __init__(self, where: str, reason: str, kept: str) -> None:
        super().__init__(f"{where}: cannot be written ({reason}); {kept}")
        self.where, self.reason, self.kept = where, reason, kept


def _refused(exc: BaseException, shown: PathLike, kept: str, fix=str) -> BaseException:
    """``exc``, or when it is the file system refusing a write a :class:`WriteRefused`
    naming the file (``shown``, or the file the error names) and what was ``kept``.

    ``fix`` turns a temporary path into the user's (:func:`_user_paths`).
    """
    if isinstance(exc, WriteRefused):
        return WriteRefused(fix(exc.where), exc.reason, kept)
    if isinstance(exc, OSError) and exc.errno in WRITE_ERRORS:
        where = exc.filename if isinstance(exc.filename, str) else str(shown)
        return WriteRefused(fix(where), exc.strerror or os.strerror(exc.errno), kept)
    return exc


def _user_paths(exc: BaseException, staged: Path, shown: PathLike) -> Callable[[str], str]:
    """Say ``shown`` (the user's path) wherever ``exc`` names ``staged`` (our temporary one).

    A check run on a staged file (a sequence read back, a 3MF validated) raises with the
    temporary file's name, which is gone once the error is printed; the user must read
    the path they gave. The message, its notes and an ``OSError``'s file names are
    rewritten in place; the rewriting is returned.
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
    return fix


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
        clean_stale(tmp_dir)
    tmp = _make_temp(
        lambda: _temp_file(tmp_dir, Path(path).suffix or ".tmp"),
        created,
        f"{path}: cannot write in {tmp_dir}",
    )
    try:
        yield tmp
        raise_if_interrupted()
        with signals_held() as held:  # a signal now: the file is the old one or the new
            _install(tmp, dest, st)
            if not any(_STALE.match(p.name) for p in dest.parents):  # not in a staging folder
                note_written(str(path))
        if held:
            raise Interrupted(held[0])
    except BaseException as exc:
        tmp.unlink(missing_ok=True)
        _remove_created(created)
        fix = _user_paths(exc, tmp, path)
        kept = "the old file is kept" if st is not None else "nothing was written"
        refused = _refused(exc, path, kept, fix)
        if refused is not exc:
            raise refused from None
        raise


@contextlib.contextmanager
def atomic_write(path: PathLike, mode: str = "w", **kwargs) -> Iterator[IO]:
    """Open a temporary file for writing; it replaces ``path`` only on success."""
    with atomic_path(path) as tmp, open(tmp, mode, **kwargs) as fh:
        yield fh


class GrowingFile:
    """An output written line by line as a run goes (``drive``'s log), in place of
    ``path`` only once :meth:`publish` says the run began.

    Until then the lines go to a temporary file beside ``path`` (into memory for a
    device or pipe) and an old file there stays as it was; one never published is
    removed on :meth:`close`. Each :meth:`write` adds whole lines or nothing: a write the
    file system refuses (:data:`WRITE_ERRORS`; raised as :class:`WriteRefused`), or an
    interrupt, cuts the file back to its last whole line. ``OutputError``: ``path`` is a
    folder, or no file can be made beside it.
    """

    def __init__(self, path: PathLike) -> None:
        self.path, self.published, self.size = path, False, 0
        self._dest, st = _target(path)
        self._stream = st is not None and not stat.S_ISREG(st.st_mode)
        self._pending: list[str] = []
        self._fd: int | None = None
        self._tmp: Path | None = None
        self._created: list[Path] = []
        if self._stream:
            return  # a device or pipe: opened when published
        self._created = _ensure_folder(self._dest.parent, path)
        clean_stale(self._dest.parent)
        self._tmp = _make_temp(
            lambda: _temp_file(self._dest.parent, self._dest.suffix or ".tmp"),
            self._created,
            f"{path}: cannot write in {self._dest.parent}",
        )
        self._fd = os.open(self._tmp, os.O_WRONLY)

    def write(self, text: str) -> None:
        """Add ``text`` (whole lines) at the end: all of it, or nothing."""
        if self._fd is None:
            self._pending.append(text)
            return
        encoded = text.encode("utf-8")
        data = memoryview(encoded)
        try:
            while data:
                data = data[os.write(self._fd, data) :]
        except BaseException as exc:
            if not self._stream:
                with contextlib.suppress(OSError):
                    os.ftruncate(self._fd, self.size)
            if isinstance(exc, OSError) and exc.errno in WRITE_ERRORS:
                reason = exc.strerror or os.strerror(exc.errno)
                raise WriteRefused(
                    str(self.path), reason, "it ends at its last whole line"
                ) from None
            raise
        self.size += len(text.encode("utf-8"))

    def flush(self) -> None:
        """Nothing to do: every :meth:`write` reaches the file system at once."""

    def publish(self) -> None:
        """The run began: the file replaces the old one at ``path``, flushed to the disk
        first; further lines go into it."""
        if self.published:
            return
        self.published = True
        try:
            if self._stream:
                self._fd = os.open(self._dest, os.O_WRONLY)
                pending, self._pending = "".join(self._pending), []
                self.write(pending)
                return
            os.fchmod(self._fd, 0o666 & ~_umask())  # mkstemp makes 0600; the usual mode
            os.fsync(self._fd)
            os.replace(self._tmp, self._dest)
        except OSError as exc:
            self.published = False
            raise _refused(
                exc, self.path, "the old file is kept", lambda _: str(self.path)
            ) from None
        _sync(self._dest.parent, folder=True)

    def close(self) -> None:
        """Close the file; one never published is removed, the old file left as it was."""
        if self._fd is not None:
            fd, self._fd = self._fd, None
            with contextlib.suppress(OSError):
                if self.published and not self._stream:
                    os.fsync(fd)
            os.close(fd)
        if not self.published and self._tmp is not None:
            self._tmp.unlink(missing_ok=True)
            _remove_created(self._created)

    def __enter__(self) -> GrowingFile:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def _staged_files(stage: Path) -> list[Path]:
    return sorted(
        p.relative_to(stage)
        for p in stage.rglob("*")
        if not p.is_dir() and not p.name.startswith(".oc-")  # a nested write cut short
    )


@contextlib.contextmanager
def atomic_directory(path: PathLike, inputs: Sequence[PathLike] = ()) -> Iterator[Path]:
    """Yield a temporary folder; on success its files are put into ``path``, all at once.

    For commands that write several files. Only the command's own files are
    written into ``path``: every other file or folder already there is kept.
    The files replace the old ones as one set (:func:`_commit`): after an
    exception, an interrupt, a full disk or even ``kill -9`` (rolled back by the
    next run, :func:`clean_stale`) the folder holds all the old files or all the
    new ones, never a mix. On an exception nothing is written, and a folder
    created for the output is removed again.

    Parameters
    ----------
    path : path-like
        The output folder; created if missing. A link to a folder is followed.
    inputs : sequence of path-like
        The command's input files: an output file that resolves to one of them, or to
        a file one of them names (:func:`referenced_files`), is an error (checked
        before anything is put in place).

    Raises
    ------
    OutputError
        ``path`` exists and is not a folder, an output would replace an input,
        a folder or a non-regular file.
    """
    shown = path
    refuse_broken_link(path, str(shown))
    folder = _real(path)
    if folder.exists() and not folder.is_dir():
        raise OutputError(f"{shown}: exists and is not a folder; give a folder for the outputs")
    created = _ensure_folder(folder, shown)
    clean_stale(folder)
    root = _make_temp(
        lambda: Path(tempfile.mkdtemp(prefix=_prefix(), dir=folder)),
        created,
        f"{shown}: cannot write in this folder",
    )
    stage = root / "files"
    try:
        stage.mkdir()
        yield stage
        raise_if_interrupted()
        plan = _plan_install(stage, folder, shown, inputs)
        _commit(root, stage, plan, shown)
    except BaseException as exc:
        with signals_held():
            shutil.rmtree(root, ignore_errors=True)
            _remove_created(created)
        fix = _user_paths(exc, stage, shown)
        refused = _refused(exc, shown, "the folder's old files are kept", fix)
        if refused is not exc:
            raise refused from None
        raise
    with signals_held() as held:
        shutil.rmtree(root, ignore_errors=True)
    if held:
        raise Interrupted(held[0])


def _plan_install(stage: Path, folder: Path, shown: PathLike, inputs: Sequence[PathLike]):
    """Where each staged file goes; every check done before anything moves."""
    protected = protected_files(inputs)
    plan = []
    for rel in _staged_files(stage):
        out = folder / rel
        refuse_broken_link(out, f"{shown}: {rel.as_posix()}")
        try:
            dest, st = _target(out)
        except OutputError:
            raise OutputError(
                f"{shown}: {rel.as_posix()} is a folder there; the output file cannot replace it"
            ) from None
        why = protection(dest, protected)
        if why is not None:
            raise OutputError(f"{shown}: the output {rel.as_posix()} {why}")
        plan.append((rel, dest, st))
    return plan


def _same_device(a: Path, b: Path) -> bool:
    try:
        return os.stat(a).st_dev == os.stat(b).st_dev
    except OSError:
        return False


def _prepare_commit(root: Path, stage: Path, plan, entries: list[dict]) -> list:
    """Before anything is replaced: each new file ready beside its target, each old
    one kept under a second name (a hard link), and the journal that lists them.

    Fills ``entries`` (the journal's) and returns the writes into devices or pipes.
    """
    streams = []
    for rel, dest, st in plan:
        src = stage / rel
        if st is not None and not stat.S_ISREG(st.st_mode):
            streams.append((src, dest, st))
            continue
        _ensure_folder(dest.parent, dest)
        os.chmod(src, 0o666 & ~_umask())  # mkstemp makes 0600; give the usual mode
        entry = {"dest": str(dest), "new": str(src), "backup": None, "id": None}
        entries.append(entry)
        if not _same_device(src, dest.parent):  # another file system: copy beside it first
            tmp = _temp_file(dest.parent, dest.suffix)
            entry["new"] = str(tmp)
            shutil.copyfile(src, tmp)
            os.chmod(tmp, 0o666 & ~_umask())
        if st is not None:
            backup = _temp_file(dest.parent, ".old")
            backup.unlink()
            entry["backup"] = str(backup)
            try:
                os.link(dest, backup)
            except OSError:  # a file system without hard links
                shutil.copy2(dest, backup)
        _sync(entry["new"])  # on the disk before any old file is replaced
        new = os.stat(entry["new"])
        entry["id"] = [new.st_dev, new.st_ino]
    _write_journal(root, {"pid": os.getpid(), "state": "commit", "entries": entries})
    return streams


def _write_journal(root: Path, data: dict) -> None:
    tmp = root / "journal.tmp"
    with open(tmp, "w", encoding="utf-8") as fh:
        json.dump(data, fh)
        fh.flush()
        os.fsync(fh.fileno())
    os.replace(tmp, root / "journal.json")


def _commit(root: Path, stage: Path, plan, shown: PathLike) -> None:
    """Put the staged files in place as one set, or not at all.

    Each target's old file is first kept under a second name and the list written to
    ``journal.json``; then every new file is renamed over its target. Ctrl-C and
    SIGTERM are held from the first step to the last. If a rename fails, or a signal
    came before the last rename, every target is given back its old file (or removed if
    it had none) and the error or :class:`Interrupted` raised. A signal after it leaves
    the whole new set (noted in ``_signals.written``) and raises :class:`Interrupted`. A
    process killed meanwhile leaves the journal, which the next run rolls back.
    """
    entries: list[dict] = []
    complete = False
    with signals_held() as held:
        try:
            streams = _prepare_commit(root, stage, plan, entries)
            try:
                for e in entries:
                    if held:  # before or between the renames: the old set comes back
                        break
                    os.replace(e["new"], e["dest"])
            except BaseException:
                _roll_back(entries)
                raise
            if held:
                _roll_back(entries)
            else:
                complete = True
                note_written(str(shown))
                for folder in {str(Path(e["dest"]).parent) for e in entries}:
                    _sync(folder, folder=True)
                _write_journal(root, {"pid": os.getpid(), "state": "done", "entries": entries})
        except OSError as exc:  # complete: only the journal's last word is missing
            what = "were put in place, unrecorded" if complete else "cannot be put in place"
            raise OutputError(f"{shown}: the outputs {what} ({exc.strerror})") from None
        finally:
            _remove_kept(entries, root)
    if held:
        raise Interrupted(held[0])
    for src, dest, st in streams:
        _install(src, dest, st)


def _remove_kept(entries: list[dict], root: Path) -> None:
    """Remove the old files kept and the new files copied beside their targets."""
    for e in entries:
        for key in ("backup", "new"):
            path = e.get(key)
            if path and _STALE.match(Path(path).name) and not Path(path).is_relative_to(root):
                with contextlib.suppress(OSError):
                    os.unlink(path)


def _ours(entry: dict) -> bool:
    """Whether the target of a journal entry holds the new file this run put there."""
    try:
        st = os.stat(entry["dest"], follow_symlinks=False)
    except OSError:
        return False
    return [st.st_dev, st.st_ino] == list(entry["id"])


def _roll_back(entries: list[dict]) -> None:
    """Give each target replaced by a journal's entry its old file back (or remove it)."""
    for e in entries:
        if not _ours(e):
            continue  # not replaced yet (or since changed by someone else): leave it
        if e["backup"] is not None:
            os.replace(e["backup"], e["dest"])
        else:
            os.unlink(e["dest"])


def _recover(root: Path) -> None:
    """Roll back the commit a killed run left half done (its ``journal.json``)."""
    try:
        journal = json.loads((root / "journal.json").read_text(encoding="utf-8"))
        entries = journal["entries"]
    except (OSError, ValueError, KeyError, TypeError):
        return  # killed before the commit began: nothing was replaced
    with contextlib.suppress(OSError, KeyError, TypeError, AttributeError):
        if journal.get("state") == "commit":
            _roll_back(entries)
        _remove_kept(entries, root)
