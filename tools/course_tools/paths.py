"""Where the course's own folders are. Standard library only: set-up imports this with
the system's Python, before .venv exists."""

from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]  # tools/course_tools/paths.py
BUILD = ROOT / "build"
