"""Writing output files safely: a temporary file in the same folder, then a rename.

A reader never sees a half-written file, and a run that fails or is killed before the rename
leaves the previous file as it was. Two runs writing the same path each write their own
temporary file, so the survivor is one complete file. A set of files (the figures of one run)
is written the same way: every member is finished first, then each is renamed into place.
Devices and pipes (``/dev/null``, ``/dev/stdout``, a FIFO) are written in place, since a
rename would replace them by a regular file.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import stat
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path

from .errors import WriteError

TEMP_PREFIX = ".vorobound-tmp-"
"""Temporary files start with this (hidden) prefix, so a killed run's leftovers are easy to spot."""


def ensure_folder(folder: str | os.PathLike) -> Path:
    """Create ``folder`` (and its parents) if needed, for outputs that go into a folder."""
    folder = Path(folder)
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise WriteError(f"cannot create folder {folder}: {exc.strerror or exc}") from None
    return folder


def checked_destination(path: str | os.PathLike) -> Path:
    """``path`` if a file can be written there: its folder exists, it is not a folder itself,
    and the folder takes a new file (a temporary one is made and removed; devices and pipes,
    written in place, are not tried). Checked before any work, so a long run does not fail at
    its last step (``sample -o /sys/x.npz`` failed after the whole sample was made)."""
    path = _placed(path)
    if not _direct(path):
        _discard(_temp_for(path))
    return path


def _placed(path: str | os.PathLike) -> Path:
    """``path`` if its folder exists and it is not a folder itself."""
    path = Path(path)
    if path.is_dir():
        raise WriteError(f"cannot write {path}: it is a folder")
    if not path.parent.is_dir():
        raise WriteError(f"cannot write {path}: folder {path.parent} does not exist")
    return path


def checked_folder(folder: str | os.PathLike) -> Path:
    """``folder`` if it is a folder or can become one (it is not an existing file)."""
    folder = Path(folder)
    if folder.exists() and not folder.is_dir():
        raise WriteError(f"cannot write into {folder}: it is a file, not a folder")
    return folder


def _direct(path: Path) -> bool:
    """True when ``path`` must be written in place: a device or a pipe (``/dev/null``,
    ``/dev/stdout``, a FIFO), which a rename would replace by a regular file. A folder in the
    way is an error."""
    try:
        mode = path.stat().st_mode
    except OSError:
        return False
    if stat.S_ISDIR(mode):
        raise WriteError(f"cannot write {path}: it is a folder")
    return not stat.S_ISREG(mode)


def _temp_for(path: Path) -> Path:
    folder = _placed(path).parent
    try:
        handle, name = tempfile.mkstemp(prefix=f"{TEMP_PREFIX}{path.name}.", dir=folder)
    except OSError as exc:
        raise WriteError(f"cannot write {path}: {exc.strerror or exc}") from None
    os.close(handle)
    return Path(name)


def _discard(temp: Path) -> None:
    with contextlib.suppress(OSError):
        temp.unlink()


def _publish(temp: Path, path: Path) -> None:
    try:
        # mkstemp creates files readable by the owner only; give the usual permissions.
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(temp, 0o666 & ~umask)
        os.replace(temp, path)
    except OSError as exc:
        _discard(temp)
        raise WriteError(f"cannot write {path}: {exc.strerror or exc}") from None


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; rename it onto ``path`` if the block succeeds.

    For writers that want a file name (matplotlib, meshio, numpy). On any exception, including
    KeyboardInterrupt, the temporary file is removed and ``path`` is untouched.
    """
    target = Path(path)
    if _direct(target):
        yield target
        return
    temp = _temp_for(target)
    try:
        yield temp
    except BaseException:
        _discard(temp)
        raise
    _publish(temp, target)


@contextlib.contextmanager
def atomic_open(path: str | os.PathLike, mode: str = "w", encoding: str = "utf-8"):
    """Like ``open(path, mode)`` for writing, but the file appears only when the block ends."""
    binary = "b" in mode
    with atomic_path(path) as temp:
        try:
            if binary:
                handle = open(temp, mode)
            else:
                handle = open(temp, mode, encoding=encoding, newline="")
        except OSError as exc:
            raise WriteError(f"cannot write {path}: {exc.strerror or exc}") from None
        with handle:
            try:
                yield handle
                handle.flush()
                if stat.S_ISREG(os.fstat(handle.fileno()).st_mode):
                    os.fsync(handle.fileno())
            except OSError as exc:
                raise WriteError(f"cannot write {path}: {exc.strerror or exc}") from None


def write_text(path: str | os.PathLike, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically; return the path."""
    with atomic_open(path, "w") as handle:
        handle.write(text)
    return Path(path)


def write_set(
    writers: dict[Path, Callable[[Path], None]], folders: dict[Path, Path] | None = None
) -> list[Path]:
    """Write several files as a set: each writer fills a temporary path, then all are renamed.

    ``writers`` maps each final path to a function that writes the file at the path it is given.
    If any writer fails (or the run is interrupted) before the renames, no final path changes.
    ``folders`` maps final folder paths to finished temporary folders (made with
    :func:`temporary_folder` beside them) that join the set: each replaces its final folder
    (a previous one is moved aside and removed once the set is in place).
    """
    folders = {Path(k): Path(v) for k, v in (folders or {}).items()}
    direct = {Path(path) for path in writers if _direct(Path(path))}  # checked before writing
    temps: dict[Path, Path] = {}
    try:
        for path, write in writers.items():
            path = Path(path)
            temps[path] = path if path in direct else _temp_for(path)
            try:
                write(temps[path])
            except OSError as exc:
                raise WriteError(f"cannot write {path}: {exc.strerror or exc}") from None
    except BaseException:
        for path, temp in temps.items():
            if path not in direct:
                _discard(temp)
        raise
    pending = [(path, temp) for path, temp in temps.items() if path not in direct]
    old_folders = []
    try:
        for final, temp in folders.items():
            old_folders.append(_publish_folder(temp, final))
        while pending:
            path, temp = pending[0]
            _publish(temp, path)
            pending.pop(0)
    except BaseException:
        for _, temp in pending:
            _discard(temp)
        raise
    finally:
        for old in old_folders:
            if old is not None:
                shutil.rmtree(old, ignore_errors=True)
    return [Path(p) for p in writers] + list(folders)


def temporary_folder(final: str | os.PathLike) -> Path:
    """An empty hidden folder beside ``final`` to fill and then publish with :func:`write_set`
    (its name starts with ``TEMP_PREFIX``; remove it with :func:`discard_folder` on failure)."""
    final = Path(final)
    if final.exists() and not final.is_dir():
        raise WriteError(f"cannot write {final}: it is a file, not a folder")
    try:
        return Path(tempfile.mkdtemp(prefix=f"{TEMP_PREFIX}{final.name}.", dir=final.parent))
    except OSError as exc:
        raise WriteError(f"cannot write {final}: {exc.strerror or exc}") from None


def discard_folder(folder: str | os.PathLike) -> None:
    """Remove a temporary folder and everything in it (no error if it is gone)."""
    shutil.rmtree(folder, ignore_errors=True)


def _publish_folder(temp: Path, final: Path) -> Path | None:
    """Rename ``temp`` onto ``final``; a previous ``final`` is renamed aside first and returned
    (the caller removes it)."""
    old = None
    try:
        if final.exists():
            old = Path(tempfile.mkdtemp(prefix=f"{TEMP_PREFIX}{final.name}.old.", dir=final.parent))
            os.replace(final, old / final.name)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(temp, 0o777 & ~umask)
        os.replace(temp, final)
    except OSError as exc:
        if old is not None and not final.exists():
            with contextlib.suppress(OSError):
                os.replace(old / final.name, final)
        discard_folder(temp)
        raise WriteError(f"cannot write {final}: {exc.strerror or exc}") from None
    return old
