"""Expensive references, kept across clones: the grader's reference renders and the
checks' Mitsuba 3 renders take most of a first run, and the same inputs always make
the same picture. So each is kept in a per-user folder,
$XDG_CACHE_HOME/gpu-ray-tracing-course/references (default ~/.cache/...; the
COURSE_REFERENCE_CACHE variable names another folder, or "off" for none), named by a
SHA-256 of everything that makes it: the program's sources, shaders and assets, the
arguments, the renderer's versions (key() below; the callers list what goes in).

An entry is one file: a header line with the payload's length and digest, then the
payload, written under a temporary name and renamed. An entry whose length or digest
does not match (a torn write, a disk error, an edit) is removed and made again, never
used. Only the user who made the folder can open it (0700): a grader keeps its
references out of a submission's reach, and hides the folder from the sandbox too.
Standard library only (the autograder image runs this)."""

from __future__ import annotations

import hashlib
import os
import threading
from pathlib import Path

MAGIC = b"course-reference-cache 1"


def folder() -> Path | None:
    """The cache folder (made on first use), or None when caching is off."""
    setting = os.environ.get("COURSE_REFERENCE_CACHE", "")
    if setting.lower() in ("off", "0", "no", "none"):
        return None
    if setting:
        path = Path(setting)
    else:
        base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
        path = Path(base) / "gpu-ray-tracing-course" / "references"
    return path


def key(*parts) -> str:
    """A SHA-256 of the parts in order: str, bytes, or a Path (its name and bytes)."""
    digest = hashlib.sha256()
    for part in parts:
        if isinstance(part, Path):
            digest.update(b"file\0" + part.name.encode() + b"\0")
            digest.update(file_digest(part).encode())
        elif isinstance(part, bytes):
            digest.update(b"bytes\0" + len(part).to_bytes(8, "little") + part)
        else:
            text = str(part).encode()
            digest.update(b"text\0" + len(text).to_bytes(8, "little") + text)
    return digest.hexdigest()


_FILE_DIGESTS: dict[tuple[str, int, int], str] = {}
_LOCK = threading.Lock()


def file_digest(path: Path) -> str:
    """SHA-256 of a file's bytes, remembered by path, size and modification time."""
    status = path.stat()
    remembered = (str(path.resolve()), status.st_size, status.st_mtime_ns)
    with _LOCK:
        if remembered in _FILE_DIGESTS:
            return _FILE_DIGESTS[remembered]
    digest = hashlib.sha256()
    with open(path, "rb") as source:
        for block in iter(lambda: source.read(1 << 20), b""):
            digest.update(block)
    with _LOCK:
        _FILE_DIGESTS[remembered] = digest.hexdigest()
    return digest.hexdigest()


def scene_as_read(data: bytes) -> bytes:
    """A scene file's bytes as the chapters' scene reader reads them
    (common/text_file.cpp): each line's comment, from '#' to its end, left out, and the
    lines kept (their numbers are in messages). A comment makes no picture, so rewording
    one, as the pages that quote a scene do, keeps what was rendered from it. A comment
    holding a control byte stays: the reader refuses the whole file for it."""
    def kept(line: bytes) -> bytes:
        code, _, comment = line.partition(b"#")
        controls = any((byte < 0x20 and byte not in (0x09, 0x0D)) or byte == 0x7F
                       for byte in comment)
        return line if controls else code
    return b"\n".join(kept(line) for line in data.split(b"\n"))


def tree_digest(*roots: Path, scenes_as_read: bool = False) -> str:
    """SHA-256 of every file under the roots (folders or files): relative names and
    contents, in sorted order. A missing root counts as empty. With scenes_as_read, a
    .scene file counts as the scene reader reads it (scene_as_read)."""
    digest = hashlib.sha256()
    for root in roots:
        digest.update(b"root\0" + root.name.encode() + b"\0")
        files = sorted(p for p in root.rglob("*") if p.is_file()) if root.is_dir() else \
            [root] if root.is_file() else []
        for path in files:
            name = path.relative_to(root).as_posix() if root.is_dir() else path.name
            content = hashlib.sha256(scene_as_read(path.read_bytes())).hexdigest() \
                if scenes_as_read and path.suffix == ".scene" else file_digest(path)
            digest.update(name.encode() + b"\0" + content.encode())
    return digest.hexdigest()


def _entry(name: str) -> Path | None:
    base = folder()
    if base is None:
        return None
    return base / name[:2] / name


def fetch(name: str) -> bytes | None:
    """The payload kept under `name` (a key() and a suffix), or None. A damaged entry
    is removed."""
    path = _entry(name)
    if path is None:
        return None
    try:
        data = path.read_bytes()
    except OSError:
        return None
    header, newline, payload = data.partition(b"\n")
    words = header.split(b" ")
    if (newline and header.startswith(MAGIC + b" ") and len(words) == 4
            and words[2].isdigit() and int(words[2]) == len(payload)
            and hashlib.sha256(payload).hexdigest().encode() == words[3]):
        return payload
    path.unlink(missing_ok=True)  # torn or tampered with: made again by the caller
    return None


def store(name: str, payload: bytes):
    """Keeps payload under `name`, whole or not at all. A cache that cannot be written
    is only a missed shortcut."""
    path = _entry(name)
    if path is None:
        return
    try:
        base = path.parent.parent
        base.mkdir(parents=True, exist_ok=True)
        os.chmod(base, 0o700)
        path.parent.mkdir(exist_ok=True)
        partial = path.with_name(f".{name}.{os.getpid()}.{threading.get_ident()}")
        header = MAGIC + b" %d %s\n" % (len(payload),
                                         hashlib.sha256(payload).hexdigest().encode())
        partial.write_bytes(header + payload)
        partial.replace(path)
    except OSError:
        pass
