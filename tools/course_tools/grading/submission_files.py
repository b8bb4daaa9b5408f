"""Files a submission wrote, read and written as a grader must: never through a link it
left, never from a FIFO or a device, never more than the sandbox lets it write; and
the grader's own files written whole or not at all."""

from __future__ import annotations

import os
import stat
import threading
from pathlib import Path

from course_tools.grading import sandbox


def read_regular(path: Path, limit: int) -> bytes:
    """The bytes of a file a submission wrote, read without following a link it may
    have left there, and never from a FIFO or a device. Raises OSError or ValueError
    with what is wrong."""
    try:
        descriptor = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK)
    except OSError as error:
        if os.path.islink(path):
            raise ValueError("left a link where the file should be (not followed)") from None
        raise error
    with os.fdopen(descriptor, "rb") as source:
        status = os.fstat(source.fileno())
        if not stat.S_ISREG(status.st_mode):
            raise ValueError("left something that is not a regular file")
        if status.st_size > limit:
            raise ValueError(f"wrote a file larger than {limit >> 20} MiB")
        return source.read(limit + 1)[:limit]


def submitted_file(path: Path) -> tuple[bytes | None, str]:
    """(its bytes, "") or (None, what is wrong), for the report."""
    try:
        return read_regular(path, sandbox.current_limits().file_mb << 20), ""
    except FileNotFoundError:
        return None, f"wrote no {path.name}"
    except (OSError, ValueError) as error:
        return None, f"{error} ({path.name})"


def write_new(path: Path, data: bytes, mode: int = 0o644):
    """Creates path (never through a link, never over a file) with data."""
    descriptor = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, mode)
    with os.fdopen(descriptor, "wb") as sink:
        sink.write(data)


def write_atomically(path: Path, data: bytes):
    """Whole or not at all, even with two graders at once."""
    partial = path.with_name(f".{path.name}.{os.getpid()}.{threading.get_ident()}")
    partial.write_bytes(data)
    partial.replace(path)


def private_folder(path: Path) -> Path:
    path.mkdir(parents=True, exist_ok=True)
    os.chmod(path, 0o700)
    return path
