"""An X server of the course's own (Xvfb) for programs that open a window: the window
tests and the Windows check under Wine. Xvfb picks a free display number itself and
reports it once it accepts clients (-displayfd), so servers started at the same time
never race for a number, unlike xvfb-run -a."""

from __future__ import annotations

import os
import select
import subprocess
import time
from contextlib import contextmanager
from pathlib import Path


class VirtualDisplayError(Exception):
    """Xvfb failed to start, or did not say it was ready in time; the message says
    which, with its log."""


@contextmanager
def xvfb(log: Path, ready_within: float):
    """Yields the display (":N") of a new Xvfb writing to `log`; stops it after."""
    ready_read, ready_write = os.pipe()
    with open(log, "wb") as log_file:
        server = subprocess.Popen(
            ["Xvfb", "-displayfd", str(ready_write), "-screen", "0", "800x600x24",
             "-nolisten", "tcp"],
            pass_fds=[ready_write], stdout=log_file, stderr=log_file,
            stdin=subprocess.DEVNULL)
    os.close(ready_write)
    try:
        yield f":{_read_display_number(ready_read, server, log, ready_within)}"
    finally:
        os.close(ready_read)
        server.terminate()
        try:
            server.wait(timeout=ready_within)
        except subprocess.TimeoutExpired:
            server.kill()
            server.wait()


def _read_display_number(ready: int, server: subprocess.Popen, log: Path,
                         ready_within: float) -> str:
    """Xvfb writes its display number and a newline to -displayfd once it accepts
    clients; an end of file first means it failed to start."""
    text = b""
    deadline = time.monotonic() + ready_within
    while not text.endswith(b"\n"):
        remaining = deadline - time.monotonic()
        if remaining <= 0 or not select.select([ready], [], [], remaining)[0]:
            server.kill()
            server.wait()
            raise VirtualDisplayError(f"Xvfb did not start within {ready_within:.0f} s: "
                                      + log.read_text(errors="replace"))
        chunk = os.read(ready, 64)
        if not chunk:
            server.wait()
            raise VirtualDisplayError(f"Xvfb failed to start (exit {server.returncode}): "
                                      + log.read_text(errors="replace"))
        text += chunk
    return text.decode().strip()
