"""./course bench (tools/bench*.py) at a tiny size: each figure is the median of repeated
runs with their range, the report names the machine and says whether it was quiet,
and the book's page changes only when --update-book asks. No check here depends on how
fast anything ran: only on the report's shape."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import BIN, ROOT, chapter_name

from course_tools import chapters, manifests
from course_tools.bench import mitsuba as bench
from course_tools.bench import bvh as bench_bvh
from course_tools.bench import common as bench_common
from course_tools.bench import grading as bench_grading

TINY = bench.Settings(size=32, spp=2, depth=3, repeat=2)  # 32²: every scene has regions
SUMMARY_KEYS = {"median", "min", "max", "spread", "runs"}


def chapters_built() -> list[str]:
    return chapters.names(ROOT)


def tiny_scenes() -> list[bench.Scene]:
    with_bvh = bench.newest_chapter_with_bvh(chapters_built())
    binaries = [BIN / "12_light_sampling", BIN / with_bvh]
    for program in binaries:
        if not program.exists():
            pytest.skip(f"{program.name} is not built")
    return [bench.Scene("cornell_box", "Cornell box", binaries[0]),
            bench.Scene("cornell_teapot", "teapot", binaries[1])]


def copy_of_the_page(tmp_path: Path) -> Path:
    page = tmp_path / "benchmarks.md"
    page.write_text(bench.PAGE.read_text())
    return page


# ---------------------------------------------------------------- the pieces

def test_versions_come_from_the_gl_strings():
    assert bench_common.llvm_version("llvmpipe (LLVM 15.0.6, 256 bits)") == "15.0.6"
    assert bench_common.mesa_version("4.5 (Core Profile) Mesa 22.3.6") == "22.3.6"
    assert bench_common.mesa_version("4.6.0 NVIDIA 550.54") is None
    assert bench_common.llvm_version("NVIDIA GeForce RTX 3060/PCIe/SSE2") is None


def test_a_summary_is_the_median_and_the_range():
    summary = bench_common.summarise([3.0, 1.0, 2.0])
    assert (summary["median"], summary["min"], summary["max"]) == (2.0, 1.0, 3.0)
    assert summary["spread"] == pytest.approx(1.0)  # (3 - 1) / 2
    assert summary["runs"] == [3.0, 1.0, 2.0]
    assert bench_common.spread_words(summary) == "1–3 (100%)"


def test_a_busy_machine_is_named_loudly():
    assert bench_common.is_quiet(0.5, 0.1, cores=2)
    assert not bench_common.is_quiet(0.7, 0.1, cores=2)  # the load at the start
    assert not bench_common.is_quiet(0.1, 0.9, cores=2)  # others' work while it ran
    # The load average lags: a bench right after another (or a build) is judged by what
    # others do just before it starts, where that was measured.
    assert bench_common.is_quiet(1.2, 0.1, cores=2, others_at_start=0.05)
    assert not bench_common.is_quiet(0.1, 0.1, cores=2, others_at_start=0.9)


def test_a_process_busy_before_the_bench_starts_is_seen():
    """A process spinning while the start is sampled shows as others' use (a child
    still running counts too: own_cpu_seconds holds only the finished renders)."""
    import subprocess
    import sys
    busy = subprocess.Popen([sys.executable, "-c", "while True: pass"])
    try:
        others = bench_common.others_cores_over(1.0)
    finally:
        busy.kill()
        busy.wait()
    if others is None:
        pytest.skip("no /proc/stat here: the load average judges the start instead")
    assert others >= 0.5
    busy = {"cores": 2, "load_start": 3.0, "load_end": 2.5,
            "other_processes_cores": 1.2, "quiet": False}
    assert "NOT quiet" in bench_common.quiet_words(busy)
    assert "NOT" not in bench_common.quiet_words({**busy, "quiet": True})


def test_the_teapot_goes_through_the_newest_chapter_with_a_bvh():
    """On the main line: the media chapters branch from chapter 18 (their manifests'
    `base`), so the speed chapters stay the bench's."""
    names = chapters_built()
    off = manifests.branches(ROOT, names)
    assert {"24_participating_media", "25_grid_media"} <= off
    assert not any(n[:2] in ("19", "20", "21", "22", "23", "30") for n in off)
    chosen = bench.newest_chapter_with_bvh(names)
    numbered = [n for n in names if n[:2].isdigit() and n not in off]
    has_bvh = ["--brute-force" in (ROOT / "chapters" / n / "main.cpp").read_text()
               for n in numbered]
    assert has_bvh[numbered.index(chosen)]
    assert not any(has_bvh[numbered.index(chosen) + 1:])


def test_the_cornell_box_goes_through_the_newest_chapter_on_the_main_line():
    """Not a branch: chapter 29 (temporal accumulation) reports samples over all its
    frames and no rays a second; the speed chapters' last one is the bench's."""
    names = chapters_built()
    off = manifests.branches(ROOT, names)
    assert {"28_denoising", "29_temporal"} <= off
    chosen = bench.newest_main_line_chapter(names)
    numbered = [n for n in names if n[:2].isdigit()]
    assert chosen not in off
    assert all(n in off for n in numbered[numbered.index(chosen) + 1:])


def test_a_table_goes_into_the_page_only_when_asked(tmp_path):
    page = copy_of_the_page(tmp_path)
    before = page.read_text()
    bench_common.book_or_not(False, page, bench.START, bench.END, "NEW TABLE")
    assert page.read_text() == before
    bench_common.book_or_not(True, page, bench.START, bench.END, "NEW TABLE")
    head, _ = before.split(bench.START, 1)
    _, tail = before.split(bench.END, 1)
    assert page.read_text() == f"{head}{bench.START}\nNEW TABLE\n{bench.END}{tail}"


MACHINE = {"cpu": "Some CPU", "cores": 2, "gl_renderer": "llvmpipe (LLVM 15.0.6, 256 bits)",
           "gl_version": "4.5 (Core Profile) Mesa 22.3.6", "mesa": "22.3.6",
           "llvm": "15.0.6", "mitsuba": "3.9.1"}
QUIET = {"cores": 2, "load_start": 0.1, "load_end": 1.9, "other_processes_cores": 0.05,
         "quiet": True}


def test_the_bvh_table_gives_medians_and_names_the_machine():
    spread = bench_common.summarise([90.0, 100.0, 110.0])
    report = {"date": "today", "machine": MACHINE, "title": MACHINE["gl_renderer"],
              "size": 96, "repeat": 3, "loop_limit": "65 535", "skipped": [], "quiet": QUIET,
              "builds": {}, "results": [
                  {"triangles": t, "rays": rays, "method": "bvh",
                   "rays_per_second": spread["median"], "spread": spread}
                  for t in bench_bvh.TEAPOTS for rays in ("primary", "diffuse")]}
    table = bench_bvh.page_table(report)
    assert "median of 3 runs" in table and "20% of its median" in table
    assert "Mesa 22.3.6 with LLVM 15.0.6" in table and "Some CPU (2 cores)" in table
    assert "The machine was quiet" in table


def test_the_machine_is_named_with_its_widest_vector_extension():
    # What decides how many lanes llvmpipe and Mitsuba run: every figure names it.
    intel = "flags\t\t: fpu sse4_2 avx avx2 avx512f avx512bw\n"
    amd = "flags\t\t: fpu sse4_2 avx avx2 fma\n"
    arm = "Features\t: fp asimd evtstrm\n"
    assert bench_common.vector_extension(intel) == "AVX-512"
    assert bench_common.vector_extension(amd) == "AVX2"
    assert bench_common.vector_extension(arm) == "NEON"
    assert bench_common.vector_extension("") == "unknown"
    assert bench_common.vector_extension() in {n for _, n in bench_common.VECTOR_EXTENSIONS} | {
        "unknown"}
    words = bench_common.machine_words({**MACHINE, "vectors": "AVX2"})
    assert "Some CPU (2 cores, AVX2)" in words
    assert "Some CPU (2 cores)" in bench_common.machine_words(MACHINE)  # an older report


def test_the_machine_names_both_renderers_lanes_and_embree():
    # llvmpipe's lanes come from its renderer string; Mitsuba's from the CPU, as Dr.Jit
    # chooses them: the ratio on an AVX-512 machine is llvmpipe's 8 against 16.
    assert bench_common.llvmpipe_lanes("llvmpipe (LLVM 15.0.6, 256 bits)") == 8
    assert bench_common.llvmpipe_lanes("llvmpipe (LLVM 19.1.7, 512 bits)") == 16
    assert bench_common.llvmpipe_lanes("NVIDIA GeForce RTX 4070/PCIe/SSE2") is None
    assert [bench_common.mitsuba_lanes(v) for v in ("AVX-512", "AVX2", "NEON")] == [16, 8, 4]
    words = bench_common.machine_words({**MACHINE, "vectors": "AVX-512", "mesa": "22.3.6",
                                        "llvmpipe_lanes": 8, "mitsuba": "3.9.1",
                                        "mitsuba_lanes": 16, "mitsuba_embree": True})
    assert words.endswith(", 8 lanes; Mitsuba's LLVM backend 16 lanes, with Embree"), words
    machine = bench_common.describe_machine(
        {"renderer": "llvmpipe (LLVM 15.0.6, 256 bits)", "gl_version": "4.5 Mesa 22.3.6"})
    assert machine["llvmpipe_lanes"] == 8 and machine["mitsuba_embree"] in (True, False, None)


def test_a_page_keeps_a_table_per_kind_of_cpu(tmp_path):
    # An Intel with AVX-512 and an AMD with AVX2 give other ratios: a bench replaces the
    # table of the kind it ran on and keeps the others, and an older table without a
    # kind is kept unless it names this machine's CPU.
    start, end = "<!-- t:start -->", "<!-- t:end -->"
    page = tmp_path / "page.md"
    page.write_text(f"Before.\n{start}\nMeasured on Old AMD (2 cores): 1.0x\n{end}\nAfter.\n")
    intel = {"cpu": "Some Xeon", "vectors": "AVX-512"}
    amd = {"cpu": "Old AMD", "vectors": "AVX2"}
    bench_common.book_or_not(True, page, start, end, "Xeon: 2.0x", intel)
    text = page.read_text()
    assert "Old AMD (2 cores): 1.0x" in text and "Xeon: 2.0x" in text
    assert text.startswith("Before.\n") and text.endswith(f"{end}\nAfter.\n")
    bench_common.book_or_not(True, page, start, end, "AMD: 3.0x", amd)  # replaces the old
    bench_common.book_or_not(True, page, start, end, "Xeon: 2.5x", intel)
    block = page.read_text().split(start)[1].split(end)[0]
    assert bench_common.tables_by_kind(block) == [("Old AMD, AVX2", "AMD: 3.0x"),
                                                  ("Some Xeon, AVX-512", "Xeon: 2.5x")]
    # A page waiting for its first quiet run says so; the first table takes its place.
    page.write_text(f"{start}\nNo quiet run of the bench is recorded here yet.\n{end}\n")
    bench_common.book_or_not(True, page, start, end, "Measured ... Xeon: 2.0x", intel)
    assert "No quiet run" not in page.read_text()


def test_the_grading_table_gives_medians_and_ranges():
    report = {"date": "today", "cpu": "Some CPU", "cores": 2, "repeat": 3,
              "gl_renderer": MACHINE["gl_renderer"], "gl_version": MACHINE["gl_version"],
              "quiet": {**QUIET, "quiet": False},
              "chapters": [{"chapter": "12_light_sampling", "tests": 4, "runs": 9,
                            "seconds": 30.0, "peak_mib": 200,
                            "spread": bench_common.summarise([29.0, 30.0, 33.0])}]}
    table = bench_grading.page_table(report)
    assert "median of 3" in table and "29.0–33.0 (13%)" in table
    assert "NOT quiet" in table


def test_the_help_names_update_book_and_repeat():
    result = subprocess.run([sys.executable, str(ROOT / "tools" / "course.py"), "bench",
                             "--help"], capture_output=True, text=True, check=True)
    assert "--update-book" in result.stdout and "--repeat" in result.stdout
    assert "median" in result.stdout


# ---------------------------------------------------------------- the bench itself, tiny

@pytest.fixture(scope="module")
def tiny_bench(tmp_path_factory):
    """One tiny bench against Mitsuba without --update-book, on a copy of the page."""
    pytest.importorskip("mitsuba", reason="pip install -r requirements.txt")
    folder = tmp_path_factory.mktemp("bench")
    page = copy_of_the_page(folder)
    book_before = bench.PAGE.read_text()
    page_before = page.read_text()
    status = bench.main(tiny_scenes(), TINY, update_book=False, page=page,
                        out_folder=folder / "out")
    report = json.loads((folder / "out" / "bench.json").read_text())
    return {"status": status, "report": report, "page": page, "page_before": page_before,
            "book_before": book_before}


def test_without_update_book_no_page_changes(tiny_bench):
    assert tiny_bench["page"].read_text() == tiny_bench["page_before"]
    assert bench.PAGE.read_text() == tiny_bench["book_before"]
    assert tiny_bench["status"] in (0, 1)  # 2 spp: the 1% check may well miss


def test_the_report_names_the_machine(tiny_bench):
    report = tiny_bench["report"]
    machine = report["machine"]
    for key in ("cpu", "cores", "gl_renderer", "gl_version", "mesa", "mitsuba"):
        assert machine[key], key
    assert "llvm" in machine  # None on a GPU
    assert machine["mitsuba"] == bench_common.mitsuba_version()
    assert report["date"]
    quiet = report["quiet"]
    assert {"load_start", "load_end", "quiet"} <= quiet.keys()
    assert isinstance(quiet["quiet"], bool)
    table = bench.page_table(report)
    assert machine["cpu"] in table and f"Mitsuba {machine['mitsuba']}" in table
    if machine["mesa"]:
        assert f"Mesa {machine['mesa']}" in table


def test_every_figure_is_a_median_of_the_runs(tiny_bench):
    report = tiny_bench["report"]
    assert report["settings"] == {"size": 32, "spp": 2, "depth": 3, "mitsuba_max_depth": 4,
                                  "repeat": 2}
    assert set(report["scenes"]) == {"cornell_box", "cornell_teapot"}
    for scene in report["scenes"].values():
        renderers = scene["renderers"]
        assert "ours" in renderers and len(renderers) >= 2, "Mitsuba ran no variant"
        for name, figures in renderers.items():
            for figure, summary in figures.items():
                assert SUMMARY_KEYS <= summary.keys(), (name, figure)
                assert len(summary["runs"]) == TINY.repeat
                assert summary["min"] <= summary["median"] <= summary["max"]
        assert "rays_per_second" in renderers["ours"]
        for variant, ratio in scene["ratios"].items():
            assert ratio["of_medians"] == pytest.approx(
                renderers[variant]["samples_per_second"]["median"]
                / renderers["ours"]["samples_per_second"]["median"])
            assert len(ratio["per_run"]["runs"]) == TINY.repeat


def test_the_region_check_is_kept(tiny_bench):
    for scene in tiny_bench["report"]["scenes"].values():
        assert scene["region_reference"] in bench.VARIANTS
        assert scene["regions"], scene["title"]
        for row in scene["regions"].values():
            assert {"pixels", "ours", "mitsuba", "relative", "relative_error"} <= row.keys()
    assert "teapot" in tiny_bench["report"]["scenes"]["cornell_teapot"]["regions"]
    table = bench.page_table(tiny_bench["report"])
    assert "| teapot | teapot |" in table and "| Cornell box | back |" in table


def test_update_book_writes_the_table_into_the_page(tmp_path):
    pytest.importorskip("mitsuba", reason="pip install -r requirements.txt")
    page = copy_of_the_page(tmp_path)
    before = page.read_text()
    bench.main(tiny_scenes()[:1], bench.Settings(size=16, spp=1, depth=2, repeat=2),
               update_book=True, page=page, out_folder=tmp_path / "out",
               variants=("scalar_rgb",))
    report = json.loads((tmp_path / "out" / "bench.json").read_text())
    head, block_before = before.split(bench.START, 1)
    block_before, tail = block_before.split(bench.END, 1)
    after = page.read_text()
    assert after.startswith(f"{head}{bench.START}\n") and after.endswith(f"{bench.END}{tail}")
    # This machine's kind of CPU gets this run's table; the other kinds' stay.
    block = after.split(bench.START, 1)[1].split(bench.END, 1)[0]
    tables = dict(bench_common.tables_by_kind(block))
    kind = bench_common.machine_kind(report["machine"])
    assert tables[kind] == bench.page_table(report).strip()
    for other, table in bench_common.tables_by_kind(block_before):
        if other != kind and not (other is None and report["machine"]["cpu"] in table):
            assert tables[other] == table
    assert "median of 2 runs" in after


@pytest.fixture
def tiny_bvh_bench(monkeypatch, tmp_path):
    """bench_bvh.main on the smallest teapot at 16², its scratch folder in tmp_path."""
    program = BIN / "14_bvh_sah"
    if not program.exists():
        pytest.skip("14_bvh_sah is not built")
    monkeypatch.setattr(bench_bvh, "TEAPOTS", (552,))
    monkeypatch.setattr(bench_bvh, "SIZE", 16)
    monkeypatch.setattr(bench_bvh, "SCRATCH", tmp_path / "scratch")
    page, figure = copy_of_the_page(tmp_path), tmp_path / "bvh_scaling.png"

    def run(update_book: bool) -> dict:
        bench_bvh.main(program, ROOT / "build" / "assets" / "meshes", repeat=2,
                       update_book=update_book, page=page, figure=figure)
        return json.loads((tmp_path / "scratch" / "bvh.json").read_text())
    return run, page, figure


def test_the_bvh_bench_repeats_and_writes_the_book_only_when_asked(tiny_bvh_bench):
    run, page, figure = tiny_bvh_bench
    before = page.read_text()
    report = run(update_book=False)
    assert page.read_text() == before and not figure.exists()
    assert report["repeat"] == 2 and report["machine"]["gl_renderer"]
    assert "load_start" in report["quiet"]
    for record in report["results"]:
        assert len(record["spread"]["runs"]) == 2
        assert record["rays_per_second"] == record["spread"]["median"]
    report = run(update_book=True)
    assert figure.exists()
    assert bench_bvh.page_table(report) in page.read_text()
    head, _ = before.split(bench_bvh.START, 1)
    _, tail = before.split(bench_bvh.END, 1)
    assert page.read_text().startswith(head) and page.read_text().endswith(tail)


# ---------------------------------------------------------------- chapters 19-21's speed bench

def page_copies(pages: dict, folder: Path) -> dict:
    """Each page of a bench copied into folder, with its markers: the bench writes there."""
    copies = {}
    for number, (page, start, end) in pages.items():
        (folder / page.name).write_text(page.read_text())
        copies[number] = (folder / page.name, start, end)
    return copies


@pytest.fixture(scope="module")
def tiny_speed_bench(tmp_path_factory):
    """bench_speed with the Cornell box's rows, the teapot's priced trees and two compile
    rows, tiny, twice over: once without --update-book (on copies of the chapters'
    pages), once with."""
    from course_tools.bench import speed as bench_speed
    binaries = {number: BIN / chapter_name(number) for number in ("18", "19", "20", "21")}
    rows = [row for row in bench_speed.ROWS if row.scene == "cornell_box" or
            (row.table == "price" and row.scene == "cornell_teapot")]
    compiled = [row for row in bench_speed.COMPILED if row.scene == "cornell_box" and
                row.label in ("buffer textures", "chapter 18")]
    folder = tmp_path_factory.mktemp("speed")
    pages = page_copies(bench_speed.PAGES, folder)
    book_before = {n: page.read_text() for n, (page, _, _) in bench_speed.PAGES.items()}
    before = {n: page.read_text() for n, (page, _, _) in pages.items()}
    settings = bench_speed.Settings(size=16, spp=1, depth=2, repeat=2)
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(bench_speed, "ROWS", tuple(rows))
        patch.setattr(bench_speed, "COMPILED", compiled)
        report = bench_speed.bench(binaries, settings)  # once: the rows' runs take most
        bench_speed.publish(report, update_book=False, pages=pages, out_folder=folder / "out")
        unchanged = all(page.read_text() == before[n] for n, (page, _, _) in pages.items())
        bench_speed.publish(report, update_book=True, pages=pages, out_folder=folder / "out")
    return {"report": json.loads((folder / "out" / "speed.json").read_text()),
            "unchanged": unchanged,
            "pages": {n: page.read_text() for n, (page, _, _) in pages.items()},
            "book_unchanged": all(page.read_text() == book_before[n]
                                  for n, (page, _, _) in bench_speed.PAGES.items())}


def test_the_speed_bench_gives_medians_of_the_runs(tiny_speed_bench):
    report = tiny_speed_bench["report"]
    assert report["machine"]["mesa"] and report["settings"]["repeat"] == 2
    for row in report["rows"].values():
        for figure in ("samples_per_second", "rays_per_second"):
            assert set(row[figure]) == SUMMARY_KEYS and len(row[figure]["runs"]) == 2
            assert row[figure]["min"] <= row[figure]["median"] <= row[figure]["max"]
    assert len(report["compile_seconds"]) == 2
    automatic = [row["label"] for row in report["rows"].values() if row["chapter"] == "18"]
    assert automatic == ["chapter 18"]
    assert {row["chapter"] for row in report["rows"].values()} == {"18", "19", "20", "21"}


def test_the_speed_bench_writes_each_chapters_page_only_when_asked(tiny_speed_bench):
    assert tiny_speed_bench["unchanged"] and tiny_speed_bench["book_unchanged"]
    pages = tiny_speed_bench["pages"]
    for page in pages.values():
        assert "Each figure is the median of 2 runs" in page
    assert "| cornell_box | chapter 19 (automatic: constants) |" in pages["19"]
    assert "| generic ÷ specialised, both storage buffers |" in pages["19"]
    assert "| cornell_box | uniform blocks |" in pages["20"]
    assert "| storage buffers ÷ buffer textures |" in pages["20"]
    for number in ("19", "21"):  # the memory table is chapter 20's alone
        assert "| uniform blocks |" not in pages[number]
    assert "| cornell_teapot | leaves priced as the walk runs them |" in pages["21"]
    assert "| leaves priced as run ÷ by count, the teapot |" in pages["21"]


# ---------------------------------------------------------- chapters 22, 23, 30 and 31's kernels bench

@pytest.fixture(scope="module")
def tiny_wavefront_bench(tmp_path_factory):
    """bench_wavefront with the Cornell box's rows, tiny, twice over: once without
    --update-book (on copies of the chapters' pages), once with."""
    from course_tools.bench import wavefront as bench_wavefront
    binaries = {number: BIN / chapter_name(number) for number in ("22", "23", "30", "31")}
    rows = tuple(bench_wavefront.Row("scenes", "cornell_box", kernel, 16)
                 for kernel in bench_wavefront.KERNELS) \
        + tuple(bench_wavefront.Row("sizes", "cornell_box", kernel, 24)
                for kernel in bench_wavefront.SIZED)
    folder = tmp_path_factory.mktemp("wavefront")
    pages = page_copies(bench_wavefront.PAGES, folder)
    book_before = {n: page.read_text() for n, (page, _, _) in bench_wavefront.PAGES.items()}
    before = {n: page.read_text() for n, (page, _, _) in pages.items()}
    settings = bench_wavefront.Settings(spp=2, depth=2, repeat=2)  # 2 a dispatch
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(bench_wavefront, "ROWS", rows)
        patch.setattr(bench_wavefront, "SCENES", (("cornell_box", "1: diffuse"),))
        report = bench_wavefront.bench(binaries, settings)  # once: the rows' runs take most
        bench_wavefront.publish(report, update_book=False, pages=pages, out_folder=folder / "out")
        unchanged = all(page.read_text() == before[n] for n, (page, _, _) in pages.items())
        bench_wavefront.publish(report, update_book=True, pages=pages, out_folder=folder / "out")
    return {"report": json.loads((folder / "out" / "wavefront.json").read_text()),
            "unchanged": unchanged,
            "pages": {n: page.read_text() for n, (page, _, _) in pages.items()},
            "book_unchanged": all(page.read_text() == book_before[n]
                                  for n, (page, _, _) in bench_wavefront.PAGES.items())}


def test_the_wavefront_bench_gives_medians_of_the_runs(tiny_wavefront_bench):
    report = tiny_wavefront_bench["report"]
    assert report["machine"]["mesa"] and report["settings"]["repeat"] == 2
    assert {row["kernel"] for row in report["rows"].values()} == {
        "megakernel", "regenerating", "wavefront", "checked", "stackless"}
    dispatches = {row["kernel"]: row["samples_per_dispatch"] for row in report["rows"].values()}
    assert dispatches == {"megakernel": 1, "regenerating": 2, "wavefront": 1, "checked": 2,
                          "stackless": 2}
    for row in report["rows"].values():
        for figure in ("samples_per_second", "rays_per_second"):
            assert set(row[figure]) == SUMMARY_KEYS and len(row[figure]["runs"]) == 2
            assert row[figure]["min"] <= row[figure]["median"] <= row[figure]["max"]


def test_the_wavefront_bench_writes_each_chapters_page_only_when_asked(tiny_wavefront_bench):
    assert tiny_wavefront_bench["unchanged"] and tiny_wavefront_bench["book_unchanged"]
    regeneration, wavefront = tiny_wavefront_bench["pages"]["22"], \
        tiny_wavefront_bench["pages"]["23"]
    for page in (regeneration, wavefront):
        assert "Each figure is the median of 2 runs" in page
        assert "| cornell_box | 24² | megakernel | 1 |" in page
        assert "| cornell_box | 24² | regenerating | 2 |" in page
        assert "| cornell_box (1: diffuse) |" in page
    assert "| cornell_box | 1: diffuse | wavefront | 1 |" in wavefront
    assert ("| samples/s ÷ megakernel's, 16² | regenerating: this machine | "
            "regenerating: your GPU | wavefront: this machine | wavefront: your GPU |") \
        in wavefront
    block = regeneration.split("<!-- regeneration:start -->")[1].split("<!-- regeneration:end -->")[0]
    assert "wavefront" not in block and "| checked |" not in block
    checked = tiny_wavefront_bench["pages"]["30"]
    assert "| cornell_box | 1: diffuse | checked | 2 |" in checked
    assert "| checked |" not in wavefront and "| wavefront |" not in checked
    # Chapter 31's page: the checked and the stackless kernel, as multiples of the
    # checked one's, and no sizes table (those kernels are not run at other sizes).
    stackless = tiny_wavefront_bench["pages"]["31"]
    block = stackless.split("<!-- stackless:start -->")[1].split("<!-- stackless:end -->")[0]
    assert "| cornell_box | 1: diffuse | stackless | 2 |" in block
    assert "| cornell_box | 1: diffuse | checked | 2 |" in block and "÷ checked |" in block
    assert "| megakernel |" not in block and "24²" not in block


def test_the_wavefront_bench_gives_the_million_triangle_teapots_ratio():
    from course_tools.bench import wavefront as bench_wavefront

    rays = {("cornell_teapot", "checked"): 4.0e6, ("cornell_teapot_million", "checked"): 2.0e6,
            ("cornell_teapot", "stackless"): 5.0e6,
            ("cornell_teapot_million", "stackless"): 3.5e6}
    report = {"rows": {bench_wavefront.row_key("scenes", scene, 48, kernel): {
        "table": "scenes", "scene": scene, "kernel": kernel, "size": 48,
        "rays_per_second": {"median": value}} for (scene, kernel), value in rays.items()}}
    lines = bench_wavefront.million_lines(report, ("checked", "stackless"))
    assert lines[0].endswith("÷ the teapot's: checked 0.50, stackless 0.70.")
    assert bench_wavefront.million_lines(report, ("megakernel",)) == []


def test_a_programs_statistics_are_its_last_json_line():
    from course_tools.program_output import last_json_line
    printed = "course: compiling\n{\"not\": \"this\"}\n{\"rays\": 12, \"renderer\": \"x\"}\n\n"
    assert last_json_line(printed) == {"rays": 12, "renderer": "x"}
    for nothing in ("", "course: it crashed\n", "[1, 2]\n"):
        with pytest.raises(ValueError, match="chapter 07 printed no JSON statistics"):
            last_json_line(nothing, "chapter 07")


# ---------------------------------------------------------------- chapter 26's instances bench

@pytest.fixture(scope="module")
def tiny_instances_bench(tmp_path_factory):
    """bench_instances with a field of 10 x 10 teapots at 16², twice over: once without
    --update-book (on copies of the pages), once with."""
    from course_tools.bench import instances as bench_instances
    program = BIN / chapter_name("26")
    if not program.exists():
        pytest.skip(f"{program.name} is not built")
    folder = tmp_path_factory.mktemp("instances")
    pages = page_copies(bench_instances.PAGES, folder)
    book_before = {n: page.read_text() for n, (page, _, _) in bench_instances.PAGES.items()}
    before = {n: page.read_text() for n, (page, _, _) in pages.items()}
    settings = bench_instances.Settings(size=16, repeat=2, grid=10)
    report = bench_instances.bench(program, ROOT / "build" / "assets" / "meshes", settings,
                                   folder / "scenes")
    bench_instances.publish(report, update_book=False, pages=pages, out_folder=folder / "out")
    unchanged = all(page.read_text() == before[n] for n, (page, _, _) in pages.items())
    bench_instances.publish(report, update_book=True, pages=pages, out_folder=folder / "out")
    return {"report": json.loads((folder / "out" / "instances.json").read_text()),
            "scenes": folder / "scenes", "unchanged": unchanged,
            "pages": {n: page.read_text() for n, (page, _, _) in pages.items()},
            "book_unchanged": all(page.read_text() == book_before[n]
                                  for n, (page, _, _) in bench_instances.PAGES.items())}


def test_the_instances_bench_gives_medians_and_the_chapters_own_counts(tiny_instances_bench):
    from python_prototypes import scene_io
    report = tiny_instances_bench["report"]
    assert report["machine"]["mesa"] and report["settings"]["repeat"] == 2
    for row in report["rows"].values():
        for figure in ("rays_per_second", "instance_tree_ms"):
            assert set(row[figure]) == SUMMARY_KEYS and len(row[figure]["runs"]) == 2
            assert row[figure]["min"] <= row[figure]["median"] <= row[figure]["max"]
    field = report["rows"]["field: primary"]
    # The field as the Python reader reads it: 100 placements of one 6 320-triangle object.
    scene = scene_io.load_scene(tiny_instances_bench["scenes"] / "field.scene")
    assert len(scene.instances) == field["instances"] == 100
    assert field["triangles"] == 6320 and field["placed_triangles"] == 100 * 6320
    one = report["rows"]["one_instance: primary"]
    assert one["instances"] == 1 and report["rows"]["written_out: primary"]["instances"] == 0
    # Memory: the teapot once, and the instances and their tree beside it.
    assert one["instance_bytes"] < field["instance_bytes"] < one["instance_bytes"] + 100 * 256


def test_the_instances_bench_writes_both_pages_only_when_asked(tiny_instances_bench):
    from course_tools.bench import instances as bench_instances
    assert tiny_instances_bench["unchanged"] and tiny_instances_bench["book_unchanged"]
    table = bench_instances.page_table(tiny_instances_bench["report"])
    for page in tiny_instances_bench["pages"].values():
        assert table in page and "Each figure is the median of 2 runs" in page
        assert "| 100 teapots | 100 | 632,000 | 6,320 |" in page


def test_the_instances_bench_says_which_target_it_missed(tiny_instances_bench):
    from course_tools.bench import instances as bench_instances
    report = json.loads(json.dumps(tiny_instances_bench["report"]))
    met = dict(bench_instances.checks(report))
    assert len(met) == 3
    # Slow the field's camera rays to a third of one teapot's, and double its memory.
    field, one = report["rows"]["field: primary"], report["rows"]["one_instance: primary"]
    field["rays_per_second"]["median"] = one["rays_per_second"]["median"] / 3
    field["instance_bytes"] = 3 * (one["instance_bytes"] + 99 * 64)
    missed = [text for text, ok in bench_instances.checks(report) if not ok]
    assert any(text.startswith("primary rays through the field: 0.33x") for text in missed)
    assert any(text.startswith("memory of the field: 3.00x") for text in missed)


# ---------------------------------------------------------------- chapter 27's refit bench

def test_the_refit_bench_times_both_trees_and_writes_the_pages_only_when_asked(tmp_path):
    from course_tools.bench import refit as bench_refit
    program = BIN / chapter_name("27")
    if not program.exists():
        pytest.skip(f"{program.name} is not built")
    pages = page_copies(bench_refit.PAGES, tmp_path)
    before = {n: page.read_text() for n, (page, _, _) in pages.items()}
    settings = bench_refit.Settings(size=16, repeat=2, twists=(90.0,))
    report = bench_refit.bench(program, ROOT / "build" / "assets" / "meshes", settings,
                               tmp_path / "scratch")
    bench_refit.publish(report, update_book=False, pages=pages, out_folder=tmp_path / "out")
    assert all(page.read_text() == before[n] for n, (page, _, _) in pages.items())
    (row,) = report["rows"]
    # The chapter's own counts: a quarter turn makes the refitted tree dearer than a
    # fresh one (test_27_motion.py checks by how much).
    assert row["refitted_sah_cost"] > row["rebuilt_sah_cost"] > 0
    for key in ("refit_ms", "rebuild_ms", "refitted_primary", "fresh_primary",
                "refitted_diffuse", "fresh_diffuse"):
        assert set(row[key]) == SUMMARY_KEYS and len(row[key]["runs"]) == 2
    bench_refit.publish(report, update_book=True, pages=pages, out_folder=tmp_path / "out")
    for page, _, _ in pages.values():
        assert bench_refit.page_table(report) in page.read_text()
        assert "| 90° | 33.40 | 27.64 | 1.21 |" in page.read_text()


# ---------------------------------------------------------------- chapter 28's denoise bench

def made_up_denoise_report() -> dict:
    """A report shaped as bench_denoise.bench() makes it (its measuring needs Mitsuba's
    references at 16 384 samples: ./course bench denoise)."""
    from course_tools.bench import denoise as bench_denoise
    summary = {"median": 1.0, "min": 0.9, "max": 1.1, "spread": 0.2, "runs": [0.9, 1.0, 1.1]}
    rows = [{"scene": scene, "name": name, "raw_bar": 0.005,
             **{str(n): {"raw": 0.3 / n, "ours": 0.02 / n, "oidn": 0.015 / n}
                for n in bench_denoise.SAMPLES}}
            for scene, name in bench_denoise.SCENES.items()]
    cost = {"denoise_ms": {**summary, "median": 150.0}, "sample_ms": {**summary, "median": 300.0},
            "oidn_ms": {**summary, "median": 200.0}, "samples": {**summary, "median": 0.5}}
    machine = bench_common.describe_machine(
        {"renderer": "llvmpipe (LLVM 15.0.6, 256 bits)",
         "gl_version": "4.5 (Core Profile) Mesa 22.3.6"})
    return {"date": "2026-12-06 21:39 UTC", "machine": machine,
            "settings": {"size": 160, "seeds": 2, "repeat": 3},
            "reference_spp": bench_denoise.REFERENCE_SPP, "rows": rows, "cost": cost,
            "quiet": {"cores": 2, "load_start": 0.1, "others_at_start": 0.0, "threshold": 0.6,
                      "quiet": True, "load_end": 0.2, "other_processes_cores": 0.0}}


def test_the_denoise_bench_draws_its_figure_and_writes_the_book_only_when_asked(tmp_path):
    from course_tools.bench import denoise as bench_denoise
    report = made_up_denoise_report()
    pages = page_copies(bench_denoise.PAGES, tmp_path)
    before = {n: page.read_text() for n, (page, _, _) in pages.items()}
    figure = tmp_path / "figures" / "denoise_error.png"
    bench_denoise.publish(report, update_book=False, pages=pages, out_folder=tmp_path / "out",
                          figure=figure)
    assert (tmp_path / "out" / "denoise_error.png").stat().st_size > 10_000
    assert not figure.exists()
    assert all(page.read_text() == before[n] for n, (page, _, _) in pages.items())
    bench_denoise.publish(report, update_book=True, pages=pages, out_folder=tmp_path / "out",
                          figure=figure)
    assert figure.read_bytes() == (tmp_path / "out" / "denoise_error.png").read_bytes()
    for page, start, end in pages.values():
        table = page.read_text().split(start)[1].split(end)[0]
        assert "| teapot | 4 |" in table and "0.50 samples a pixel" in table, table
