"""Output files: the one check of a path to write (:func:`output_path`) and atomic writing that
a signal cannot interrupt half-way (:func:`atomic_write`)."""

from __future__ import annotations

import os
import signal
import stat
import tempfile
import threading
from collections.abc import Callable
from pathlib import Path

__all__ = ["atomic_write", "check_scene_name", "output_path"]

#: What a file that is not a regular file is, by its ``stat`` type.
_KINDS = ((stat.S_ISFIFO, "a FIFO"), (stat.S_ISCHR, "a character device"),
          (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))

#: The signals a write defers: Ctrl-C, and what ``timeout`` and batch schedulers send.
_SIGNALS = (signal.SIGINT, signal.SIGTERM)


def output_path(path, *, what: str = "output file", folder_must_exist: bool = False) -> Path:
    """The file to write for ``path``, checked before anything is computed.

    ``path`` must name a regular file that may be written, or a new name in a writable folder.
    A symbolic link is written through: the result is the file it points to (also where the
    link dangles), and the link itself stays. Missing folders on the way are allowed (the
    writer creates them) unless ``folder_must_exist``, provided the nearest existing one is a
    writable folder.

    Parameters
    ----------
    path : str or os.PathLike
        The path as given (a command-line option, a scene key).
    what : str, keyword-only
        How the messages name it, e.g. ``"-o"`` or ``"--figure"``.
    folder_must_exist : bool, keyword-only
        Refuse a path whose folder does not exist yet.

    Returns
    -------
    pathlib.Path
        The absolute path of the file that will be written (symbolic links resolved).

    Raises
    ------
    ValueError
        One line naming ``what`` and the path: an empty path; a path ending in a separator;
        an existing folder, FIFO, device node or socket; a read-only file; a path under a
        file; a folder that is missing (with ``folder_must_exist``) or not writable (a
        read-only folder or file system); a symbolic-link loop.

    Examples
    --------
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     output_path(os.path.join(folder, "new.nc")).name
    'new.nc'
    >>> output_path(os.devnull, what="-o")
    Traceback (most recent call last):
    ...
    ValueError: -o '/dev/null' is a character device, not a regular file; give a file name
    """
    text = os.fsdecode(path)
    if not text.strip():
        raise ValueError(f"{what}: empty file name; give a file name")
    if text.endswith(("/", os.sep)):
        raise ValueError(f"{what} {text!r} ends in a separator (a folder); give a file name")
    shown = f"{what} {text!r}"
    real = Path(os.path.realpath(text))
    try:
        info = os.stat(real)
    except (FileNotFoundError, NotADirectoryError):  # a new name, or a path under a file
        info = None
    except OSError as exc:                           # a link loop, a name too long, no access
        raise ValueError(f"{shown}: {(exc.strerror or str(exc)).lower()}") from None
    if info is not None:
        if stat.S_ISDIR(info.st_mode):
            raise ValueError(f"{shown} is a folder; give a file name")
        if not stat.S_ISREG(info.st_mode):
            kind = next((k for test, k in _KINDS if test(info.st_mode)), "not a regular file")
            raise ValueError(f"{shown} is {kind}, not a regular file; give a file name")
        if not os.access(real, os.W_OK):
            raise ValueError(f"{shown} is read-only; it is left as it is")
    folder = real.parent
    while not os.path.lexists(folder):
        folder = folder.parent
    if not folder.is_dir():
        raise ValueError(f"{shown}: {str(folder)!r} is a file, not a folder")
    if folder_must_exist and folder != real.parent:
        raise ValueError(f"{shown}: folder {str(real.parent)!r} does not exist")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise ValueError(f"{shown}: folder {str(folder)!r} is not writable")
    return real


def atomic_write(path, write: Callable[[str], None]) -> Path:
    """Call ``write(tmp)`` on a temporary file next to ``path``, then rename it to ``path``.

    ``path`` is checked first (:func:`output_path`: a regular file or a new name in a writable
    folder; a symbolic link is written through to its target and kept); missing folders are
    created. An interrupted or failing write never leaves a half-written ``path``: the
    previous file (if any) stays as it was and the temporary file is removed. SIGINT (Ctrl-C)
    and SIGTERM that arrive during the write are held until ``write`` returns (raising an
    exception inside a netCDF writer can deadlock it); then the temporary file is removed,
    ``path`` is left as it was, and the signal is delivered as usual (``KeyboardInterrupt``,
    or the process ends by SIGTERM). A second such signal during the write ends the process
    at once, with the temporary file removed and exit status 128 + the signal number. (Signals
    are held only when called from the main thread, where Python runs their handlers.) The
    result gets the permissions of the file it replaces, else those of a new file
    (``mkstemp`` alone would make it private).

    Returns
    -------
    pathlib.Path
        ``path`` as given.
    """
    real = output_path(path)
    real.parent.mkdir(parents=True, exist_ok=True)
    mode = (os.stat(real).st_mode & 0o777) if real.exists() else None
    caught: list[int] = []
    tmp: list[str] = []
    previous = _hold_signals(caught, tmp)
    try:
        fd, name = tempfile.mkstemp(prefix=f".{real.name}.", suffix=".tmp", dir=real.parent)
        tmp.append(name)
        os.close(fd)
        if mode is None:
            umask = os.umask(0)
            os.umask(umask)
            mode = 0o666 & ~umask
        os.chmod(name, mode)
        write(name)
        if not caught:
            os.replace(name, real)
    finally:
        if tmp and os.path.exists(tmp[0]):
            os.unlink(tmp[0])
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        if caught:                               # KeyboardInterrupt, or the end by SIGTERM
            signal.raise_signal(caught[0])
    return Path(path)


def _hold_signals(caught: list, tmp: list) -> dict:
    """Replace the SIGINT and SIGTERM handlers by one that records the signal in ``caught``
    (a second one removes the temporary file named in ``tmp`` and exits); return the handlers
    replaced. Nothing is replaced off the main thread or for a signal that is ignored."""
    if threading.current_thread() is not threading.main_thread():
        return {}

    def hold(signum, frame):
        if caught:                               # asked twice: give up the write now
            if tmp and os.path.exists(tmp[0]):
                os.unlink(tmp[0])
            os._exit(128 + signum)
        caught.append(signum)

    previous = {}
    for sig in _SIGNALS:
        handler = signal.getsignal(sig)
        if handler in (signal.SIG_IGN, None):    # None: a handler set outside Python
            continue
        previous[sig] = signal.signal(sig, hold)
    return previous


def check_scene_name(name) -> str:
    """Check a scene's ``name``: a plain file name, as the default output is ``<name>.nc``.

    Raises ``ValueError`` naming the key for an empty name, one starting with ``.`` (hidden,
    or ``..``), or one with a path separator (``/`` or ``\\``) or a NUL; returns ``name``.
    """
    if not isinstance(name, str) or not name.strip() or name.startswith(".") \
            or any(c in name for c in "/\\\0"):
        raise ValueError(f"scene key name must be a plain file name (not empty, no '/' or "
                         f"'\\', not starting with '.'); got {name!r}")
    return name
