"""What each chapter's scene reader accepts comes from its manifest (scene_reads), and
the message for what it does not names the first chapter that reads it, also from the
manifests: the common layer knows no chapter numbers (cmake/SceneSupport.cmake writes
each chapter's scene_support.h). Checked here: the headers the build wrote against the
manifests, every scene-reading chapter passing its kSceneSupport, and the messages."""

from __future__ import annotations

import re

import pytest
from conftest import ROOT, run_chapter

from course_tools import chapters, manifests

SCENES = ROOT / "assets" / "scenes"
SCENE_READERS = [name for name in chapters.names(ROOT)
                 if "loadSceneFile" in (ROOT / "chapters" / name / "main.cpp").read_text()]
FIELD = re.compile(r'^\s*\{(true|false), "([^"]*)"\},\s*// (\w+)$', flags=re.M)


def expected_support() -> dict[str, dict[str, tuple[bool, str]]]:
    """chapter -> feature -> (read, first chapter that reads it), from the manifests."""
    found = manifests.load(ROOT, chapters.names(ROOT))
    first = {}
    for name in sorted(n for n in found if n[:2].isdigit()):
        for feature in found[name].scene_reads:
            first.setdefault(feature, f"chapter {name[:2]}")
    return {name: {feature: (True, "") if feature in manifest.scene_reads
                   else (False, first.get(feature, ""))
                   for feature in manifests.SCENE_FEATURES}
            for name, manifest in found.items()}


def test_every_scene_reading_chapter_passes_what_its_manifest_says():
    assert len(SCENE_READERS) >= 10
    for name in SCENE_READERS:
        main = (ROOT / "chapters" / name / "main.cpp").read_text()
        assert '#include "scene_support.h"' in main, name
        calls = re.findall(r"loadSceneFile\((.*?)\);", main, flags=re.S)
        assert calls and all(call.rstrip().endswith("kSceneSupport") for call in calls), name


@pytest.mark.parametrize("name", SCENE_READERS)
def test_the_built_header_agrees_with_the_manifests(name):
    header = ROOT / "build" / "generated" / name / "scene_support.h"
    fields = {feature: (read == "true", chapter)
              for read, chapter, feature in FIELD.findall(header.read_text())}
    assert list(fields) == list(manifests.SCENE_FEATURES)
    assert fields == expected_support()[name]


def test_the_features_come_in_the_order_the_chapters_teach_them():
    support = expected_support()
    firsts = {feature: chapter for name in support
              for feature, (read, chapter) in support[name].items() if not read and chapter}
    assert firsts == {"metals": "chapter 15", "glass": "chapter 16", "lens": "chapter 17",
                      "textures": "chapter 17", "environment": "chapter 18",
                      "media": "chapter 24", "instances": "chapter 26",
                      "motion": "chapter 27"}
    numbered = [name for name in chapters.numbered(ROOT) if name in SCENE_READERS]
    found = manifests.load(ROOT, numbered)
    for earlier, later in zip(numbered, numbered[1:]):
        # A chapter reads what the one it was copied from reads: the one before it, or
        # its base when it branches (chapters 24 and 26 from 18, 27 from 26).
        base = found[later].base or earlier
        assert set(support[base]) and all(
            support[later][f][0] for f, (read, _) in support[base].items() if read), later


def test_a_manifest_naming_an_unknown_feature_is_a_clear_error(tmp_path):
    manifest = tmp_path / "15_metals.ini"
    manifest.write_text("[chapter]\ntitle = Metals\nsummary = s.\nscene_reads = metals fog\n")
    with pytest.raises(manifests.ManifestError, match="scene_reads: fog is not one of"):
        manifests.read(manifest)


LENS_ONLY = ("camera eye 0 0 0 look 0 0 -1 up 0 1 0 focal 0.035 sensor 0.025 lens 0.1 "
             "focus 2\nmaterial m albedo 0.5 0.5 0.5 emission 1 1 1\nsphere 0 0 -2 1 m\n")


@pytest.mark.parametrize("chapter, scene, message", [
    ("12", "cornell_metals", "'mirror' is a mirror: this program renders only diffuse "
     "materials ('albedo R G B'); mirrors and conductors come in chapter 15"),
    ("15", "cornell_glass", "is a dielectric: this program renders only opaque materials "
     "(albedo, mirror, conductor); glass comes in chapter 16"),
    ("16", LENS_ONLY, ":1: the camera has a lens: this program has a pinhole camera; the "
     "thin lens comes in chapter 17"),
    ("16", "lens_textures", "this program has no textures; textures come in chapter 17"),
    ("17", "sky_showcase", "this program has no environment light; it comes in chapter 18"),
], ids=["metals", "glass", "lens", "textures", "environment"])
def test_a_program_names_the_chapter_that_reads_what_it_cannot(tmp_path, chapter, scene,
                                                                message):
    path = SCENES / f"{scene}.scene"
    if "\n" in scene:
        path = tmp_path / "lens.scene"
        path.write_text(scene)
    result = run_chapter(chapter, "--headless", "--scene", path, "--out", tmp_path / "x.png")
    assert result.returncode == 3, result.stderr
    assert message in result.stderr
