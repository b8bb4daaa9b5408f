"""course_tools.virtual_display, with stand-ins for Xvfb on PATH: a server that reports
its display is used and stopped after; one that fails is an error that says so."""

from __future__ import annotations

import os

import pytest

from course_tools import virtual_display


def fake_xvfb(tmp_path, monkeypatch, script: str):
    folder = tmp_path / "bin"
    folder.mkdir()
    program = folder / "Xvfb"
    program.write_text("#!/bin/bash\n" + script + "\n")  # dash: one-digit fds only
    program.chmod(0o755)
    monkeypatch.setenv("PATH", f"{folder}{os.pathsep}{os.environ['PATH']}")


def test_the_reported_display_is_yielded_and_the_server_stopped(tmp_path, monkeypatch):
    # "$2" is the descriptor after -displayfd; the server writes its number there.
    fake_xvfb(tmp_path, monkeypatch, 'echo $$ > "$(dirname "$0")/pid"\necho 7 >&"$2"\nexec sleep 600')
    with virtual_display.xvfb(tmp_path / "xvfb.log", 30) as display:
        assert display == ":7"
        pid = int((tmp_path / "bin" / "pid").read_text())
        os.kill(pid, 0)  # running
    with pytest.raises(ProcessLookupError):
        os.kill(pid, 0)


def test_a_server_that_fails_to_start_is_an_error_with_its_log(tmp_path, monkeypatch):
    fake_xvfb(tmp_path, monkeypatch, 'echo "no screens found" >&2\nexit 3')
    with pytest.raises(virtual_display.VirtualDisplayError,
                       match=r"failed to start \(exit 3\): no screens found"):
        with virtual_display.xvfb(tmp_path / "xvfb.log", 30):
            pass


def test_a_server_that_never_says_it_is_ready_is_an_error(tmp_path, monkeypatch):
    fake_xvfb(tmp_path, monkeypatch, "exec sleep 600")
    with pytest.raises(virtual_display.VirtualDisplayError, match="did not start within 1 s"):
        with virtual_display.xvfb(tmp_path / "xvfb.log", 1):
            pass
