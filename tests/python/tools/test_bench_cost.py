"""./course bench cost (tools/course_tools/bench/cost.py): a sample's cost is the difference
between two renders' instruction counts over the samples it adds.

Valgrind itself takes a minute and more a render (it counts the shader's compilation
too), so here a stand-in plays it: it runs the real chapter program, as valgrind would,
and reports a count that the test knows, one that grows by a set number of
instructions a sample. The bench must find that number again, whatever the start-up
adds, and a folder of shaders must come out as the multiple the stand-in gave it."""

from __future__ import annotations

import json
import shutil
import sys
from pathlib import Path

import pytest
from conftest import BIN, ROOT, chapter_name

from course_tools.bench import cost as bench_cost

START_UP = 987_654_321  # what every run counts before its first sample (compiling ...)
PER_SAMPLE = 1_000      # what the stand-in counts a sample with the chapter's own shaders
CHANGED = 1.25          # ... and with a folder of changed shaders

# Runs the program after valgrind's own options, as valgrind does, and says on stderr
# what callgrind would: a count that the test chose. It refuses to count in an
# environment where llvmpipe could use threads or a cached shader.
STAND_IN = f'''
import os, subprocess, sys
words = [w for w in sys.argv[1:] if not w.startswith("--tool=")
         and not w.startswith("--callgrind-out-file=")]
if os.environ.get("LP_NUM_THREADS") != "0" or \\
        os.environ.get("MESA_SHADER_CACHE_DISABLE") != "true":
    sys.exit(9)
result = subprocess.run(words, capture_output=True, text=True)
sys.stdout.write(result.stdout)
value = lambda name: int(words[words.index(name) + 1])
samples = value("--spp") * value("--width") * value("--height")
per_sample = {PER_SAMPLE} * ({CHANGED} if "--shader-dir" in words else 1)
sys.stderr.write(result.stderr)
sys.stderr.write("==4242== Collected : %d\\n" % ({START_UP} + per_sample * samples))
sys.exit(result.returncode)
'''


@pytest.fixture(scope="module")
def stand_in(tmp_path_factory) -> str:
    folder = tmp_path_factory.mktemp("valgrind")
    script = folder / "valgrind"
    script.write_text(f"#!{sys.executable}\n{STAND_IN}")
    script.chmod(0o755)
    return str(script)


@pytest.fixture(scope="module")
def counted(stand_in, tmp_path_factory) -> dict:
    """The bench through chapter 30 at 16², 1 and 3 samples a pixel, with a copy of the
    chapter's shaders as the changed folder; once without --update-book and once with
    (without the folder, as the bench asks)."""
    binary = BIN / chapter_name("30")
    if not binary.exists():
        pytest.skip(f"{binary.name} is not built")
    folder = tmp_path_factory.mktemp("cost")
    changed = folder / "changed_shaders"
    shutil.copytree(ROOT / "shaders" / chapter_name("30"), changed)
    page = folder / "benchmarks.md"
    page.write_text(f"# Benchmarks\n\n{bench_cost.START}\nnone yet\n{bench_cost.END}\n")
    before = page.read_text()
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(bench_cost, "SIZE", 16)
        patch.setattr(bench_cost, "LOW_SPP", 1)
        patch.setattr(bench_cost, "HIGH_SPP", 3)
        bench_cost.main(binary, [str(changed)], valgrind=stand_in,
                        out=folder / "with_folder.json", page=page)
        unchanged = page.read_text() == before
        bench_cost.main(binary, [], update_book=True, valgrind=stand_in,
                        out=folder / "own.json", page=page)
    return {"report": json.loads((folder / "with_folder.json").read_text()),
            "own": json.loads((folder / "own.json").read_text()),
            "unchanged": unchanged, "page": page.read_text(), "changed": str(changed)}


def test_a_sample_costs_the_difference_over_the_samples_added(counted):
    rows = counted["report"]["rows"]
    assert [(row["scene"], bool(row["shader_dir"])) for row in rows] == [
        ("cornell_teapot", False), ("cornell_box", False),
        ("cornell_teapot", True), ("cornell_box", True)]
    for row in rows:
        assert row["samples"] == 16 * 16 * 2
        expected = PER_SAMPLE * (CHANGED if row["shader_dir"] else 1)
        assert row["per_sample"] == pytest.approx(expected, rel=1e-12)  # start-up cancels
        assert row["per_ray"] == pytest.approx(row["per_sample"] * row["samples"] / row["rays"])
        assert row["rays"] > row["samples"]  # the paths bounce: more rays than samples


def test_the_table_gives_each_folder_as_a_multiple_of_the_chapters_own(counted):
    report = counted["report"]
    text = bench_cost.table(report)
    assert f"`{counted['changed']}` | 1,250 |" in text and "| 1.250 |" in text
    assert "the chapter's own | 1,000 |" in text and "| 1.000 |" in text
    assert report["chapter"] == "30" and report["machine"]["gl_renderer"]
    assert report["valgrind"]  # the counter's version is named, as the renderer's is


def test_the_page_changes_only_when_asked_and_gets_the_chapters_own_counts(counted):
    assert counted["unchanged"]
    page = counted["page"]
    assert "none yet" not in page and "Measured" in page and "callgrind" in page
    assert "<!-- measured on:" in page  # one table per kind of CPU
    assert "the chapter's own | 1,000 |" in page and "1,250" not in page


def test_a_count_is_read_from_callgrinds_summary():
    stderr = "==7== Events    : Ir\n==7== Collected : 1996938395\n==7==\n"
    assert bench_cost.instructions(stderr, "a render") == 1996938395
    with pytest.raises(SystemExit, match="no callgrind count in the output of a render"):
        bench_cost.instructions("Segmentation fault\n", "a render")


def test_what_the_bench_cannot_do_it_says(tmp_path, stand_in):
    binary = BIN / chapter_name("30")
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(bench_cost.shutil, "which", lambda name: None)
        with pytest.raises(SystemExit, match="valgrind not found.*apt install valgrind"):
            bench_cost.main(binary, [], out=tmp_path / "cost.json", page=tmp_path / "p.md")
    with pytest.raises(SystemExit, match="no folder of shaders at /no/such/folder"):
        bench_cost.main(binary, ["/no/such/folder"], valgrind=stand_in,
                        out=tmp_path / "cost.json", page=tmp_path / "p.md")
    with pytest.raises(SystemExit, match="without --shader-dirs"):
        bench_cost.main(binary, [str(tmp_path)], update_book=True, valgrind=stand_in,
                        out=tmp_path / "cost.json", page=tmp_path / "p.md")
    assert not (tmp_path / "cost.json").exists()  # nothing half-written


def test_the_counting_runs_have_one_thread_and_no_shader_cache():
    environment = bench_cost.counting_environment()
    assert environment["LP_NUM_THREADS"] == "0"
    assert environment["MESA_SHADER_CACHE_DISABLE"] == "true"
    words = bench_cost.command("valgrind", Path("30"), bench_cost.Row("cornell_box", ""),
                               4, Path("out.pfm"))
    assert words[:3] == ["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null"]
    assert "--shader-dir" not in words and words[words.index("--spp") + 1] == "4"
