"""Opening untrusted files: regular files only, never blocking, reads bounded.

Used for the model file itself and for matrix files (docs/security.md).

Examples
--------
>>> import tempfile, os
>>> with tempfile.TemporaryDirectory() as folder:
...     path = os.path.join(folder, "m.toml")
...     _ = open(path, "w").write("title = 'x'")
...     with open_regular_file(path, follow_symlinks=False, max_bytes=100) as handle:
...         read_bounded(handle, 100)
b"title = 'x'"
"""

from __future__ import annotations

import errno
import os
import stat
from typing import IO


class FileRefused(ValueError):
    """A file that is not read; the message says why and is safe to show."""


# -- opening files -----------------------------------------------------------------------------

def open_regular_file(path: str | os.PathLike[str], *, follow_symlinks: bool,
                      max_bytes: int) -> IO[bytes]:
    """Open a regular file for reading without blocking on FIFOs or devices.

    ``O_NONBLOCK`` makes opening a FIFO return at once; ``fstat`` on the open
    descriptor then refuses everything but a regular file (no race between a
    check and the open).  Files larger than ``max_bytes`` are refused; callers
    still read at most ``max_bytes + 1`` bytes.
    """
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0) \
        | getattr(os, "O_BINARY", 0)
    if not follow_symlinks:
        flags |= getattr(os, "O_NOFOLLOW", 0)
    try:
        fd = os.open(path, flags)
    except OSError as exc:
        raise FileRefused(_os_reason(exc)) from None
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            raise FileRefused(f"it is not a regular file but {_file_kind(info.st_mode)}")
        if info.st_size > max_bytes:
            raise FileRefused(f"the file is {info.st_size} bytes; limited to {max_bytes}")
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise


def read_bounded(handle: IO[bytes], max_bytes: int) -> bytes:
    """At most ``max_bytes`` bytes of ``handle``; more is an error (never trusts st_size)."""
    data = handle.read(max_bytes + 1)
    if len(data) > max_bytes:
        raise FileRefused(f"the file is larger than {max_bytes} bytes; limited to {max_bytes}")
    return data


def _os_reason(exc: OSError) -> str:
    reasons = {errno.ENOENT: "no such file", errno.ENOTDIR: "no such file",
               errno.EACCES: "permission denied", errno.EPERM: "permission denied",
               errno.ELOOP: "it is a symbolic link", errno.ENXIO: "it is not a regular file",
               errno.EISDIR: "it is a directory"}
    return reasons.get(exc.errno or 0, "it cannot be opened")


def _file_kind(mode: int) -> str:
    for test, name in ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
                       (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
                       (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return name
    return "a special file"


__all__ = ["FileRefused", "open_regular_file", "read_bounded"]
