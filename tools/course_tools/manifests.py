"""One manifest per chapter, manifests/NN_name.ini: what the course's tools need to know
of a chapter besides its code. Its title and one-line summary (the book's navigation
and index), the options `./course run NN` uses when given none, the numbered chapter an
appendix was copied from (the diff its page shows), and the book's pictures with the
programs that render them. Standard library only: ./course reads it before any set-up.

    [chapter]
    title = Path tracing
    summary = Monte Carlo integration prototyped in numpy, ...
    run = --width 400 --height 400 --spp 64      (optional)
    base = 12_light_sampling                     (appendices only)
    scene_reads = metals glass                   (optional: what its scene reader
                                                  accepts besides diffuse shapes and a
                                                  pinhole camera; cmake/SceneSupport.cmake)

    [figures]
    11_direct.png = 11 --width 200 --height 200 --spp 64 --direct
    11_mc_light.png = python_prototypes/monte_carlo.py --which light --seed 1

A figure's program is a chapter's number or a script in python_prototypes/; the rest
of the line is its arguments. Grading tests stay in tools/course_tools/grading/grading_specs.py: they are
the instructor's, and a starter carries its chapter's manifest."""

from __future__ import annotations

import configparser
import re
from dataclasses import dataclass, field
from pathlib import Path

FOLDER = "manifests"
# What a scene reader may accept besides diffuse shapes and a pinhole camera, as
# cmake/SceneSupport.cmake and common/course/scene_file.h's SceneSupport name them.
SCENE_FEATURES = ("metals", "glass", "lens", "textures", "environment", "media", "instances",
                  "motion")


class ManifestError(Exception):
    """A manifest that is missing, unreadable or incomplete: file:line and what."""


@dataclass(frozen=True)
class Figure:
    name: str       # the PNG's file name, e.g. "11_direct.png"
    program: str    # a chapter's number ("11", "A2") or "python_prototypes/x.py"
    arguments: str  # the rest of the line, as the program takes it


@dataclass(frozen=True)
class Manifest:
    chapter: str    # the folder name, e.g. "11_path_tracing"
    title: str
    summary: str
    run: list[str] = field(default_factory=list)
    base: str | None = None
    figures: list[Figure] = field(default_factory=list)
    scene_reads: tuple[str, ...] = ()

    @property
    def number(self) -> str:
        return self.chapter.split("_")[0]


def read(path: Path) -> Manifest:
    parser = configparser.ConfigParser(interpolation=None, delimiters=("=",))
    parser.optionxform = str  # figure names keep their case
    try:
        parser.read_string(path.read_text(), str(path))
    except (OSError, configparser.Error) as error:
        raise ManifestError(f"{path}: {error}") from None
    if not parser.has_section("chapter"):
        raise ManifestError(f"{path}:1: no [chapter] section")
    chapter = parser["chapter"]
    for key in ("title", "summary"):
        if not chapter.get(key, "").strip():
            raise ManifestError(f"{path}: [chapter] needs a {key}")
    unknown = set(chapter) - {"title", "summary", "run", "base", "scene_reads"}
    if unknown:
        raise ManifestError(f"{path}: [chapter] has unknown keys: {', '.join(sorted(unknown))}")
    scene_reads = tuple(chapter.get("scene_reads", "").split())
    strange = [word for word in scene_reads if word not in SCENE_FEATURES]
    if strange:
        raise ManifestError(f"{path}: [chapter] scene_reads: {', '.join(strange)} is not one "
                            f"of {' '.join(SCENE_FEATURES)}")
    figures = []
    if parser.has_section("figures"):
        for name, line in parser["figures"].items():
            words = line.split(maxsplit=1)
            if not re.fullmatch(r"[\w.-]+\.png", name) or not words:
                raise ManifestError(f"{path}: [figures] '{name} = {line}': expected "
                                    "NAME.png = PROGRAM ARGUMENTS")
            figures.append(Figure(name, words[0], words[1] if len(words) > 1 else ""))
    return Manifest(chapter=path.stem, title=chapter["title"].strip(),
                    summary=" ".join(chapter["summary"].split()),
                    run=chapter.get("run", "").split(), base=chapter.get("base") or None,
                    figures=figures, scene_reads=scene_reads)


def load(root: Path, chapters: list[str]) -> dict[str, Manifest]:
    """The manifests of `chapters` (folder names), in that order; each must exist."""
    manifests = {}
    for name in chapters:
        path = root / FOLDER / f"{name}.ini"
        if not path.exists():
            raise ManifestError(f"{path}: missing: every chapter has a manifest "
                                f"(copy another chapter's and edit it)")
        manifests[name] = read(path)
    return manifests


def branches(root: Path, chapters: list[str]) -> set[str]:
    """The numbered chapters off the course's main line. The main line runs from chapter
    01, each of its chapters built on the newest main-line chapter before it (its
    manifest's `base`, or else the numbered chapter before it); any other chapter
    branches off: 24 from 18, as the appendix does from 12, and 25-29 after it. The speed
    chapters are the main line's tip: 19-23, and 30 goes on from 23."""
    numbered = [name for name in chapters if name[:2].isdigit()]
    off, tip = set(), None
    for previous, name in zip([None] + numbered, numbered):
        parent = read(root / FOLDER / f"{name}.ini").base or previous
        if parent == tip:
            tip = name
        else:
            off.add(name)
    return off
