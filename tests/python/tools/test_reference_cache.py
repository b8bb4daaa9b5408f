"""The per-user reference cache (tools/course_tools/reference_cache.py): an entry comes back whole or
not at all, a damaged one is made again and never used, and a grading reference's key
changes with every input that makes the picture, so that a change anywhere renders
anew instead of comparing with a stale picture."""

from __future__ import annotations

import shutil
import stat
import subprocess

import pytest

from conftest import ROOT

from course_tools.grading import grader
from course_tools import reference_cache

BUILD = ROOT / "build"
CHAPTER = "02_first_pixels"
ARGUMENTS = ["--width", "24", "--height", "16", "--dispatch", "2d"]


@pytest.fixture
def cache(tmp_path, monkeypatch):
    folder = tmp_path / "cache"
    monkeypatch.setenv("COURSE_REFERENCE_CACHE", str(folder))
    return folder


def entry_path(cache, name):
    return cache / name[:2] / name


def test_an_entry_comes_back_whole_and_private(cache):
    name = reference_cache.key("picture", 1) + ".png"
    assert reference_cache.fetch(name) is None
    reference_cache.store(name, b"\x89PNG pixels")
    assert reference_cache.fetch(name) == b"\x89PNG pixels"
    assert stat.S_IMODE(cache.stat().st_mode) == 0o700


@pytest.mark.parametrize("damage", [
    lambda data: data[:-3],                     # torn: the write stopped short
    lambda data: data[:-1] + bytes([data[-1] ^ 1]),  # one bit flipped on the disk
    lambda data: data.replace(b" 1 ", b" 2 ", 1),    # another format's header
    lambda data: b"",                            # an empty file
    lambda data: data + b"more",                 # something appended
], ids=["torn", "bit flipped", "other format", "empty", "appended"])
def test_a_damaged_entry_is_never_used_and_is_made_again(cache, damage):
    name = reference_cache.key("picture", 2) + ".pfm"
    reference_cache.store(name, b"PF\n1 1\n-1.0\n" + bytes(12))
    path = entry_path(cache, name)
    path.write_bytes(damage(path.read_bytes()))
    assert reference_cache.fetch(name) is None
    assert not path.exists()
    reference_cache.store(name, b"again")
    assert reference_cache.fetch(name) == b"again"


def test_off_keeps_nothing(tmp_path, monkeypatch):
    monkeypatch.setenv("COURSE_REFERENCE_CACHE", "off")
    assert reference_cache.folder() is None
    reference_cache.store("ab.png", b"x")
    assert reference_cache.fetch("ab.png") is None


def test_an_unwritable_cache_is_only_a_missed_shortcut(tmp_path, monkeypatch):
    in_the_way = tmp_path / "file"
    in_the_way.write_text("a file where the cache folder would be\n")
    monkeypatch.setenv("COURSE_REFERENCE_CACHE", str(in_the_way / "cache"))
    reference_cache.store("ab.png", b"x")
    assert reference_cache.fetch("ab.png") is None


def test_keys_tell_their_parts_apart(tmp_path):
    assert reference_cache.key("ab", "c") != reference_cache.key("a", "bc")
    assert reference_cache.key("1") != reference_cache.key(b"1")
    one, two = tmp_path / "one" / "tree", tmp_path / "two" / "tree"  # the same name
    one.mkdir(parents=True), two.mkdir(parents=True)
    (one / "a.txt").write_text("same")
    (two / "a.txt").write_text("same")
    assert reference_cache.tree_digest(one) == reference_cache.tree_digest(two)
    (two / "a.txt").write_text("other")
    assert reference_cache.tree_digest(one) != reference_cache.tree_digest(two)
    (two / "a.txt").write_text("same")
    (two / "b.txt").write_text("")
    assert reference_cache.tree_digest(one) != reference_cache.tree_digest(two)
    (two / "b.txt").rename(two / "c.txt")
    before = reference_cache.tree_digest(two)
    (two / "c.txt").rename(two / "d.txt")
    assert reference_cache.tree_digest(two) != before


def test_a_scene_counts_as_its_reader_reads_it(tmp_path):
    # The reader (common/text_file.cpp) drops each line's comment and keeps the line:
    # rewording a comment keeps the key; a number, a new line, or a control byte in a
    # comment (which the reader refuses) makes another.
    tree = tmp_path / "assets"
    tree.mkdir()
    scene = tree / "room.scene"

    def digest(text: bytes) -> str:
        scene.write_bytes(text)
        return reference_cache.tree_digest(tree, scenes_as_read=True)

    first = digest(b"# a room\nsphere 0 0 0 1 white  # the ball\n")
    assert digest(b"# a room, reworded\nsphere 0 0 0 1 white  # a ball\n") == first
    assert digest(b"# a room\nsphere 0 0 0 2 white  # the ball\n") != first
    assert digest(b"\n# a room\nsphere 0 0 0 1 white  # the ball\n") != first
    assert digest(b"# a room\x01\nsphere 0 0 0 1 white  # the ball\n") != first
    # Other files, and scenes without scenes_as_read, count byte for byte.
    scene.write_bytes(b"# a room\nsphere 0 0 0 1 white  # the ball\n")
    raw = reference_cache.tree_digest(tree)
    scene.write_bytes(b"# a room, reworded\nsphere 0 0 0 1 white  # a ball\n")
    assert reference_cache.tree_digest(tree) != raw
    (tree / "notes.txt").write_bytes(b"# one")
    before = reference_cache.tree_digest(tree, scenes_as_read=True)
    (tree / "notes.txt").write_bytes(b"# two")
    assert reference_cache.tree_digest(tree, scenes_as_read=True) != before


# ---------------------------------------------------------------- the grader's references

@pytest.fixture
def instructor_tree(tmp_path):
    """A copy of what makes chapter 02's references, to change one thing at a time."""
    root = tmp_path / "root"
    for part in (f"chapters/{CHAPTER}", f"shaders/{CHAPTER}", "common", "cmake",
                 "third_party", "assets"):
        shutil.copytree(ROOT / part, root / part)
    shutil.copyfile(ROOT / "CMakeLists.txt", root / "CMakeLists.txt")
    return root


def maker(root, build=BUILD):
    grader._MAKERS.clear()
    return grader.reference_maker(root, build, CHAPTER)


CHANGES = {
    "the chapter's host code": lambda root: append(root / "chapters" / CHAPTER / "main.cpp"),
    "the chapter's shaders": lambda root: append(root / "shaders" / CHAPTER / "pattern.glsl"),
    "the common layer": lambda root: append(root / "common" / "session.cpp"),
    "the build files": lambda root: append(root / "CMakeLists.txt", "set(X 1)\n"),
    "the chapter's own build line": lambda root: (root / "CMakeLists.txt").write_text(
        (root / "CMakeLists.txt").read_text().replace(f"add_chapter({CHAPTER})",
                                                      f"add_chapter({CHAPTER}) # x")),
    "a scene file": lambda root: append(root / "assets" / "scenes" / "cornell_box.scene",
                                        "material x albedo 1 1 1\n"),
    "a new asset": lambda root: (root / "assets" / "new.txt").write_text("x"),
}


def append(path, text="// x\n"):
    path.write_text(path.read_text() + text)


@pytest.mark.parametrize("change", CHANGES)
def test_every_input_of_a_reference_changes_its_key(instructor_tree, change):
    before = maker(instructor_tree)
    assert maker(instructor_tree) == before  # the same inputs, the same key
    CHANGES[change](instructor_tree)
    assert maker(instructor_tree) != before, change


def test_another_chapter_added_or_removed_keeps_the_key(instructor_tree):
    """A new chapter's add_chapter line builds another program: the chapter's references
    (and every render and figure keyed by them) stay."""
    before = maker(instructor_tree)
    cmake = instructor_tree / "CMakeLists.txt"
    text = cmake.read_text()
    assert "add_chapter(01_buffer_add)" in text
    cmake.write_text(text.replace("add_chapter(01_buffer_add)\n", "") +
                     "add_chapter(99_a_new_one)\n")
    assert maker(instructor_tree) == before
    cmake.write_text(text.replace(f"add_chapter({CHAPTER})\n", ""))
    assert maker(instructor_tree) != before  # its own line is its build


def test_the_renderer_and_its_settings_are_in_the_key(instructor_tree, monkeypatch):
    before = maker(instructor_tree)
    monkeypatch.setenv("LP_NATIVE_VECTOR_WIDTH", "128")
    assert maker(instructor_tree) != before
    monkeypatch.delenv("LP_NATIVE_VECTOR_WIDTH")
    real_run = subprocess.run

    def another_mesa(command, **kwargs):
        result = real_run(command, **kwargs)
        if "--probe-loop-limit" in command:
            result.stdout = result.stdout.replace("Mesa ", "Mesa 99.")
        return result
    monkeypatch.setattr(grader.subprocess, "run", another_mesa)
    assert maker(instructor_tree) != before


def test_a_reference_is_rendered_once_then_kept(tmp_path, cache, monkeypatch):
    renders = []
    real_run = subprocess.run

    def counted(command, **kwargs):
        if "--out" in command:
            renders.append(command)
        return real_run(command, **kwargs)
    monkeypatch.setattr(grader.subprocess, "run", counted)
    first, second = tmp_path / "first.png", tmp_path / "second.png"
    grader.render_reference(ROOT, BUILD, CHAPTER, ARGUMENTS, first, timeout=120)
    grader.render_reference(ROOT, BUILD, CHAPTER, ARGUMENTS, second, timeout=120)
    assert len(renders) == 1 and first.read_bytes() == second.read_bytes()
    # Other arguments (the same picture, drawn another way): rendered all the same.
    grader.render_reference(ROOT, BUILD, CHAPTER, ARGUMENTS[:-1] + ["1d"],
                            tmp_path / "third.png", timeout=120)
    assert len(renders) == 2
    # A damaged entry is rendered again, never copied.
    [entry] = [p for p in cache.rglob("*.png") if p.name.startswith(
        reference_cache.key(grader.reference_maker(ROOT, BUILD, CHAPTER), *ARGUMENTS))]
    entry.write_bytes(entry.read_bytes()[:-10])
    grader.render_reference(ROOT, BUILD, CHAPTER, ARGUMENTS, tmp_path / "fourth.png",
                            timeout=120)
    assert len(renders) == 3 and (tmp_path / "fourth.png").read_bytes() == first.read_bytes()
    assert entry.read_bytes().endswith(first.read_bytes())  # and kept whole again


# ---------------------------------------------------------------- a submission's runs

def submission(tmp_path, name="submission"):
    folder = tmp_path / name
    for top in ("chapters", "shaders"):
        shutil.copytree(ROOT / top / CHAPTER, folder / top / CHAPTER)
    return folder


def replay_or_run(kept, arguments, out, calls, code=0, data=b"PF picture"):
    """KeptRuns.run with a stand-in for the program: counts the real runs."""
    def runner():
        calls.append(arguments)
        if code == 0:
            out.write_bytes(data)
        return code, "printed"
    return kept.run(arguments, out, runner)


def test_a_kept_run_is_replayed_only_while_its_inputs_are_the_same(tmp_path, cache):
    calls = []
    source = submission(tmp_path)
    kept = grader.KeptRuns(ROOT, BUILD, CHAPTER, source)
    first = tmp_path / "first.pfm"
    assert replay_or_run(kept, ARGUMENTS, first, calls) == (0, "printed")
    again = tmp_path / "again.pfm"
    assert replay_or_run(grader.KeptRuns(ROOT, BUILD, CHAPTER, source), ARGUMENTS, again,
                         calls, data=b"not this") == (0, "printed")
    assert len(calls) == 1 and again.read_bytes() == b"PF picture"
    # Other arguments, another output kind, another submission file: run anew.
    replay_or_run(kept, ARGUMENTS + ["--seed", "2"], tmp_path / "a.pfm", calls)
    replay_or_run(kept, ARGUMENTS, tmp_path / "a.png", calls)
    append(source / "shaders" / CHAPTER / "pattern.glsl")
    replay_or_run(grader.KeptRuns(ROOT, BUILD, CHAPTER, source), ARGUMENTS,
                  tmp_path / "b.pfm", calls)
    assert len(calls) == 4
    # The solution's side (reference_maker's inputs, tested above) is in the key too.
    tree = tmp_path / "root"
    for part in (f"chapters/{CHAPTER}", f"shaders/{CHAPTER}", "common", "cmake",
                 "third_party", "assets"):
        shutil.copytree(ROOT / part, tree / part)
    shutil.copyfile(ROOT / "CMakeLists.txt", tree / "CMakeLists.txt")
    grader._MAKERS.clear()
    before = grader.KeptRuns(tree, BUILD, CHAPTER, source).prefix
    append(tree / "common" / "session.cpp")
    grader._MAKERS.clear()
    assert grader.KeptRuns(tree, BUILD, CHAPTER, source).prefix != before


def test_a_failed_run_is_never_kept_and_a_damaged_one_is_run_again(tmp_path, cache):
    calls = []
    kept = grader.KeptRuns(ROOT, BUILD, CHAPTER, submission(tmp_path))
    out = tmp_path / "out.pfm"
    assert replay_or_run(kept, ARGUMENTS, out, calls, code=3) == (3, "printed")
    assert replay_or_run(kept, ARGUMENTS, out, calls, code=None) == (None, "printed")
    assert len(calls) == 2 and kept.made == 0 and not list(cache.rglob("*.run"))
    replay_or_run(kept, ARGUMENTS, out, calls)
    [entry] = cache.rglob("*.run")
    entry.write_bytes(entry.read_bytes()[:-2])
    out.unlink()
    assert replay_or_run(kept, ARGUMENTS, out, calls) == (0, "printed")
    assert len(calls) == 4 and out.read_bytes() == b"PF picture"
    assert kept.replayed == 0 and kept.made == 2


def test_a_grading_with_kept_runs_scores_as_the_first(tmp_path, cache):
    """Chapter 02 graded twice with keep_runs: the second replays every run and gives
    the same results; without keep_runs nothing is kept."""
    source = submission(tmp_path)
    first, second = {}, {}
    results = grader.grade(ROOT, BUILD, CHAPTER, source, tmp_path / "g1", keep_runs=True,
                           kept_counts=first)
    again = grader.grade(ROOT, BUILD, CHAPTER, source, tmp_path / "g2", keep_runs=True,
                         kept_counts=second)
    runs = len(grader.SPECS[CHAPTER[:2]])
    assert first == {"replayed": 0, "made": runs} and second == {"replayed": runs, "made": 0}
    assert [t["score"] for t in again["tests"]] == [t["score"] for t in results["tests"]]
    assert again["score"] == sum(t["max_score"] for t in again["tests"])
    kept_before = sorted(cache.rglob("*.run"))
    grader.grade(ROOT, BUILD, CHAPTER, source, tmp_path / "g3")
    assert sorted(cache.rglob("*.run")) == kept_before


# ---------------------------------------------------------------- the checks' own renders

def test_a_checks_render_is_keyed_by_what_its_arguments_name(tmp_path):
    """path_checks.path_trace keeps a chapter's render under kept_render_key: a file or
    folder an argument names counts by its contents (and a scene by the files beside
    it), not by where it is; the output never counts."""
    import path_checks
    shaders = tmp_path / "one" / "shaders"
    shutil.copytree(ROOT / "shaders" / "16_glass", shaders)
    scene = tmp_path / "one" / "room.scene"
    scene.write_text("camera 0 1 4  0 1 0\n")
    (tmp_path / "one" / "gem.obj").write_text("v 0 0 0\n")
    out = tmp_path / "one" / "out.pfm"

    def key(folder=tmp_path / "one"):
        return path_checks.kept_render_key("16", ["--scene", str(folder / "room.scene"),
                                                  "--shader-dir", str(folder / "shaders"),
                                                  "--spp", "4"], folder / "out.pfm")
    before = key()
    out.write_bytes(b"an old output")
    assert key() == before  # the output is not an input
    shutil.copytree(tmp_path / "one", tmp_path / "two")
    assert key(tmp_path / "two") == before  # the same contents elsewhere
    append(shaders / "dielectric.glsl")
    assert key() != before
    shutil.rmtree(shaders)
    shutil.copytree(ROOT / "shaders" / "16_glass", shaders)
    assert key() == before
    (tmp_path / "one" / "gem.obj").write_text("v 0 0 1\n")  # a mesh the scene names
    assert key() != before
    assert key(tmp_path / "two") == before
    assert path_checks.kept_render_key("16", ["--spp", "4"], out) != \
        path_checks.kept_render_key("16", ["--spp", "8"], out)


def test_a_scene_naming_its_meshes_by_absolute_path_is_keyed_by_their_contents(tmp_path):
    """close_up writes its meshes' absolute paths: the same close-up from another clone
    names other paths to the same bytes, and must be the same render."""
    import path_checks
    keys = []
    for clone, vertex in (("one", "0"), ("two", "0"), ("three", "1")):
        mesh = tmp_path / clone / "assets" / "gem.obj"
        mesh.parent.mkdir(parents=True)
        mesh.write_text(f"v 0 0 {vertex}\n")
        scene = tmp_path / clone / "scene" / "close_up_gem.scene"
        scene.parent.mkdir()
        scene.write_text(f"mesh {mesh} glass\n")
        keys.append(path_checks.kept_render_key("16", ["--scene", str(scene)],
                                                scene.parent / "out.pfm"))
    assert keys[0] == keys[1] != keys[2]


def test_a_mitsuba_render_is_keyed_by_the_prototypes_that_translate_its_scene():
    """kept_mitsuba's key holds the prototypes mitsuba_reference imports, at any depth
    (a lazy import inside a function too), and not the others: a new prototype or
    figure script keeps every kept Mitsuba render."""
    from course_tools import mitsuba_cache
    names = {p.relative_to(ROOT).as_posix() for p in mitsuba_cache.translating_sources()}
    assert {"python_prototypes/mitsuba_reference.py", "python_prototypes/scene_io.py",
            "python_prototypes/thin_lens.py",  # imported inside a function
            "python_prototypes/pfm.py"} <= names
    assert "python_prototypes/instances.py" not in names
    assert "python_prototypes/bvh_2d.py" not in names


def test_a_prototype_figure_is_keyed_by_its_script_and_what_it_imports(tmp_path, monkeypatch):
    """A book figure drawn by a prototype is kept under its script and the prototypes it
    imports: changing one of those draws it again, a new or changed prototype it does
    not import keeps it (as a Mitsuba render's key does)."""
    from course_tools.cli import book
    prototypes = tmp_path / "python_prototypes"
    prototypes.mkdir()
    (prototypes / "__init__.py").write_text("")
    (prototypes / "curves.py").write_text("def curve():\n    return 1\n")
    (prototypes / "curves_figures.py").write_text(
        "from python_prototypes.curves import curve\nprint(curve())\n")
    (prototypes / "other.py").write_text("x = 1\n")
    monkeypatch.setattr(book, "ROOT", tmp_path)
    monkeypatch.setattr(book, "BUILD", tmp_path / "build")
    program = "python_prototypes/curves_figures.py"
    first = book.figure_key(program, ["--size", "64"])
    (prototypes / "other.py").write_text("x = 2\n")
    (prototypes / "denoise.py").write_text("y = 3\n")
    assert book.figure_key(program, ["--size", "64"]) == first
    assert book.figure_key(program, ["--size", "32"]) != first
    (prototypes / "curves.py").write_text("def curve():\n    return 2\n")
    assert book.figure_key(program, ["--size", "64"]) != first
