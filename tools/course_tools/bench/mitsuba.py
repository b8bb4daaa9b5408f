"""./course bench mitsuba: our path tracer against Mitsuba 3, on the Cornell box and on
the teapot in the Cornell room.

Same scenes (assets/scenes/cornell_box.scene, which is mitsuba.cornell_box(), and
cornell_teapot.scene, its room with the 6 320-triangle teapot), same resolution, samples
per pixel and depth (ours --depth N = Mitsuba max_depth N + 1): the Cornell box through
chapter 12 (NEE + MIS, every ray against every shape), the teapot through the newest
chapter with a BVH, against Mitsuba's `path` integrator in its scalar_rgb and
llvm_ad_rgb variants.

After an untimed warm-up render of each side (shader and kernel compilation), each
figure is measured --repeat times and reported as the median of the runs with their
range. The runs take turns (ours, then each Mitsuba variant, then ours again...),
so that a machine growing busier or quieter during the bench slows both sides alike,
and the speed ratios are the ratios of the medians. The report names the machine (CPU,
cores, Mesa, LLVM, Mitsuba) and says whether it was quiet (bench_common.QuietWatch).
Each region's mean is checked against Mitsuba's (within 1%, or the exit code is 1).

Writes build/bench/bench.json and prints the tables; writes them into
book/docs/benchmarks.md only with update_book (./course bench --update-book)."""

from __future__ import annotations

import json
import subprocess
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from course_tools import manifests
from course_tools.bench import common as bench_common
from course_tools.paths import ROOT
from course_tools.program_output import last_json_line
from python_prototypes.pfm import read_pfm

PAGE = ROOT / "book" / "docs" / "benchmarks.md"
START, END = "<!-- bench:start -->", "<!-- bench:end -->"
OUT = ROOT / "build" / "bench"
SCENES = ROOT / "assets" / "scenes"
MESH_FOLDERS = (ROOT / "build" / "assets",)
VARIANTS = ("scalar_rgb", "llvm_ad_rgb")
AGREEMENT = 0.01  # each region's mean within 1% of Mitsuba's
SMALLEST_REGION = 20  # pixels


@dataclass
class Scene:
    """A scene of the comparison, and the chapter program that renders our side."""
    name: str      # its file in assets/scenes, without .scene
    title: str     # how the tables call it
    binary: Path   # build/bin/NN_chapter
    key: str = ""  # its key in the report (default: name)

    @property
    def path(self) -> Path:
        return SCENES / f"{self.name}.scene"


@dataclass
class Settings:
    size: int = 256
    spp: int = 128
    depth: int = 6
    repeat: int = 3


def main_line(chapters: list[str], root: Path = ROOT) -> list[str]:
    """The numbered chapters that are not branches (manifests.branches: the media,
    instances, motion and denoising chapters, which build on an earlier checkpoint
    rather than on the speed chapters), in course order."""
    off = manifests.branches(root, chapters)
    return [name for name in chapters if name[:2].isdigit() and name not in off]


def newest_main_line_chapter(chapters: list[str], root: Path = ROOT) -> str:
    """The newest speed chapter, which the Cornell box's second row measures: a branch
    renders what it adds, not faster."""
    return main_line(chapters, root)[-1]


def newest_chapter_with_bvh(chapters: list[str], root: Path = ROOT) -> str:
    """The last chapter on the main line whose program has --brute-force, i.e. a BVH to
    turn off."""
    with_bvh = [name for name in main_line(chapters, root) if
                "--brute-force" in (root / "chapters" / name / "main.cpp").read_text()]
    if not with_bvh:
        raise SystemExit("bench: no chapter has a BVH (--brute-force) to render the teapot")
    return with_bvh[-1]


# ---------------------------------------------------------------- one run of each side

def run_ours(scene: Scene, settings: Settings):
    """(image, the chapter's --json statistics) for one render of our side."""
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder) / "ours.pfm"
        result = subprocess.run(
            [str(scene.binary), "--headless", "--scene", str(scene.path),
             "--width", str(settings.size), "--height", str(settings.size),
             "--spp", str(settings.spp), "--depth", str(settings.depth),
             "--estimator", "mis", "--out", str(out), "--json"],
            capture_output=True, text=True)
        if result.returncode != 0:
            raise SystemExit(f"bench: {scene.binary.name} failed on {scene.path.name} "
                             f"({result.returncode}):\n{result.stderr}")
        stats = last_json_line(result.stdout, scene.binary.name)
        return read_pfm(out), stats


def our_figures(stats: dict) -> dict:
    return {"seconds": stats["wall_ms"] / 1000,
            "samples_per_second": stats["samples_per_second"],
            "rays_per_second": stats["rays_per_second"]}


def run_mitsuba(loaded_scene, settings: Settings, variant: str):
    """(image, figures) for one render by Mitsuba; its time is mitsuba.render()'s alone."""
    from python_prototypes import mitsuba_reference
    image, stats = mitsuba_reference.render_mitsuba(
        loaded_scene, settings.size, settings.size, settings.spp, settings.depth, seed=0,
        variant=variant)
    return np.asarray(image)[..., :3], {"seconds": stats["seconds"],
                                        "samples_per_second": stats["samples_per_second"]}


# ---------------------------------------------------------------- the region check

def compare(scene, ours: np.ndarray, theirs: np.ndarray) -> dict:
    """Per region: our mean, Mitsuba's, relative difference and its standard error."""
    from python_prototypes import mitsuba_reference
    masks = {name: mask for name, mask in
             mitsuba_reference.region_masks(scene, ours.shape[1], ours.shape[0]).items()
             if mask.sum() >= SMALLEST_REGION}  # smaller regions are too noisy to compare
    mine = mitsuba_reference.region_means(ours, masks)
    reference = mitsuba_reference.region_means(theirs, masks)
    errors = mitsuba_reference.region_standard_errors(ours, theirs, masks)
    rows = {}
    for name, mask in masks.items():
        # The relative difference of the regions' brightness (mean over RGB).
        a, b, e = mine[name].mean(), reference[name].mean(), errors[name].mean()
        rows[name] = {"pixels": int(mask.sum()), "ours": float(a), "mitsuba": float(b),
                      "relative": float(a / b - 1), "relative_error": float(e / b)}
    return rows


# ---------------------------------------------------------------- one scene, repeated

@dataclass
class Runs:
    """What one scene's runs gave: each side's figures run by run, each side's first
    image, our first run's --json statistics, and the Mitsuba variants that could not
    run, with why."""
    figures: dict
    first_images: dict = field(default_factory=dict)
    first_stats: dict | None = None
    unavailable: dict = field(default_factory=dict)

    def add(self, side: str, image: np.ndarray, figures: dict):
        self.figures[side].append(figures)
        self.first_images.setdefault(side, image)


def measure_scene(scene: Scene, settings: Settings, variants=VARIANTS,
                  mesh_folders=MESH_FOLDERS) -> tuple[dict, dict]:
    """Renders the scene settings.repeat times on each side, the sides taking turns.
    Returns (the scene's report, our first run's --json statistics)."""
    from python_prototypes import scene_io
    loaded = scene_io.load_scene(str(scene.path), [str(f) for f in mesh_folders])
    runs = Runs({"ours": [], **{variant: [] for variant in variants}})
    warm_up(scene, loaded, settings, variants)
    for round_number in range(1, settings.repeat + 1):
        print(f"{scene.title}, run {round_number} of {settings.repeat}:", end=" ")
        one_round(scene, loaded, settings, variants, runs)
    for variant, why in runs.unavailable.items():
        print(f"  mitsuba {variant} skipped: {why}")
        del runs.figures[variant]
    return scene_report(scene, loaded, runs), runs.first_stats


def one_round(scene: Scene, loaded, settings: Settings, variants, runs: Runs):
    """Ours once, then each Mitsuba variant once."""
    print("ours ...", end=" ", flush=True)
    image, stats = run_ours(scene, settings)
    runs.first_stats = runs.first_stats or stats
    runs.add("ours", image, our_figures(stats))
    for variant in (v for v in variants if v not in runs.unavailable):
        print(f"mitsuba {variant} ...", end=" ", flush=True)
        try:
            runs.add(variant, *run_mitsuba(loaded, settings, variant))
        except Exception as error:  # a missing libLLVM: say so, keep the rest
            runs.unavailable[variant] = str(error).splitlines()[0] if str(error) else \
                type(error).__name__
    print("done", flush=True)


def warm_up(scene: Scene, loaded, settings: Settings, variants):
    """One untimed render of each side at 1 sample per pixel: Mesa compiles our shader
    (and keeps it in its disk cache) and Dr.Jit its kernels for this image size the
    first time, and the timed runs should not count that."""
    print(f"{scene.title}, warm-up (1 spp, not timed) ...", flush=True)
    once = Settings(settings.size, 1, settings.depth, 1)
    run_ours(scene, once)
    for variant in variants:
        try:
            run_mitsuba(loaded, once, variant)
        except Exception:  # measure_scene says why when the timed run fails too
            pass


def scene_report(scene: Scene, loaded, runs: Runs) -> dict:
    """Medians and spreads of each side, the speed ratios and the region check."""
    renderers = {side: summarise_runs(figures) for side, figures in runs.figures.items()}
    ours = [run["samples_per_second"] for run in runs.figures["ours"]]
    ratios = {}
    for variant in (side for side in runs.figures if side != "ours"):
        theirs = [run["samples_per_second"] for run in runs.figures[variant]]
        ratios[variant] = {
            "of_medians": renderers[variant]["samples_per_second"]["median"]
            / renderers["ours"]["samples_per_second"]["median"],
            "per_run": bench_common.summarise([t / o for t, o in zip(theirs, ours)])}
    images = runs.first_images
    reference = next((v for v in VARIANTS if v in images), None)
    regions = compare(loaded, images["ours"], images[reference]) if reference else {}
    return {"title": scene.title, "scene": scene.path.name,
            "chapter": runs.first_stats["chapter"], "renderers": renderers,
            "ratios": ratios, "region_reference": reference, "regions": regions,
            "unavailable": runs.unavailable}


def summarise_runs(runs: list[dict]) -> dict:
    """{figure: median, range and spread over the runs} for each figure the runs have."""
    return {figure: bench_common.summarise([run[figure] for run in runs])
            for figure in runs[0]}


# ---------------------------------------------------------------- the whole bench

def bench(scenes: list[Scene], settings: Settings, variants=VARIANTS,
          mesh_folders=MESH_FOLDERS) -> dict:
    watch = bench_common.QuietWatch()
    report = {"date": bench_common.today(),
              "settings": {"size": settings.size, "spp": settings.spp,
                           "depth": settings.depth, "mitsuba_max_depth": settings.depth + 1,
                           "repeat": settings.repeat},
              "scenes": {}}
    for scene in scenes:
        report["scenes"][scene.key or scene.name], stats = measure_scene(
            scene, settings, variants, mesh_folders)
        report.setdefault("machine", bench_common.describe_machine(stats))
    report["quiet"] = watch.finish()
    return report


def largest_region_difference(report: dict) -> tuple[float, str]:
    """(|relative difference|, 'scene: region') of the region furthest from Mitsuba's."""
    rows = [(abs(row["relative"]), f"{scene['title']}: {region}")
            for scene in report["scenes"].values()
            for region, row in scene["regions"].items()]
    return max(rows, default=(0.0, "no region large enough"))


# ---------------------------------------------------------------- the tables

def heading(report: dict) -> str:
    settings, machine = report["settings"], report["machine"]
    mitsuba = f"Mitsuba {machine['mitsuba']}" if machine.get("mitsuba") else "no Mitsuba"
    return (f"Measured {report['date']} on {bench_common.machine_words(machine)} and "
            f"{mitsuba}; {settings['size']}², {settings['spp']} spp, depth "
            f"{settings['depth']} (Mitsuba `max_depth` {settings['mitsuba_max_depth']}). "
            f"Each figure is the median of {settings['repeat']} runs, ours and Mitsuba's "
            "taking turns, with the range of the runs and its width relative to the "
            f"median. {bench_common.quiet_words(report['quiet'])}")


def speed_rows(scene: dict) -> list[str]:
    rows = []
    for name, figures in scene["renderers"].items():
        samples = figures["samples_per_second"]
        if name == "ours":
            who = f"ours, `{scene['chapter']}`"
            rays = f"{figures['rays_per_second']['median']:,.0f}"
            ratio = "1"
        else:
            who = f"Mitsuba `{name}`"
            rays = "—"
            per_run = scene["ratios"][name]["per_run"]
            ratio = (f"{scene['ratios'][name]['of_medians']:.2f}× "
                     f"({per_run['min']:.2f}–{per_run['max']:.2f})")
        title = scene["title"] if name == "ours" else ""
        rows.append(f"| {title} | {who} | {figures['seconds']['median']:.2f} | "
                    f"{samples['median']:,.0f} | {bench_common.spread_words(samples)} | "
                    f"{rays} | {ratio} |")
    for variant, why in scene["unavailable"].items():
        rows.append(f"| | Mitsuba `{variant}` | — | — | — | — | not run: {why} |")
    return rows


def region_rows(scene: dict) -> list[str]:
    return [f"| {scene['title']} | {name} | {row['pixels']} | {row['ours']:.4f} | "
            f"{row['mitsuba']:.4f} | {100 * row['relative']:+.2f}% | "
            f"{100 * row['relative_error']:.2f}% |" for name, row in scene["regions"].items()]


def page_table(report: dict) -> str:
    lines = [heading(report), "",
             "| scene | renderer | seconds | samples/s | range of the runs (spread) | "
             "rays/s | speed ÷ ours (range) |",
             "| --- | --- | ---: | ---: | ---: | ---: | ---: |"]
    for scene in report["scenes"].values():
        lines += speed_rows(scene)
    references = {scene["region_reference"] for scene in report["scenes"].values()}
    lines += ["", "Each region's mean (RGB averaged) against Mitsuba "
              f"{', '.join(f'`{r}`' for r in sorted(filter(None, references)))} "
              "(from the first run of each side: for a fixed seed every run gives the "
              "same image):", "",
              "| scene | region | pixels | ours | Mitsuba | difference | standard error |",
              "| --- | --- | ---: | ---: | ---: | ---: | ---: |"]
    for scene in report["scenes"].values():
        lines += region_rows(scene)
    return "\n".join(lines)


def main(scenes: list[Scene], settings: Settings, update_book: bool = False,
         page: Path = PAGE, out_folder: Path = OUT, variants=VARIANTS,
         mesh_folders=MESH_FOLDERS) -> int:
    report = bench(scenes, settings, variants, mesh_folders)
    out_folder.mkdir(parents=True, exist_ok=True)
    out = out_folder / "bench.json"
    out.write_text(json.dumps(report, indent=2) + "\n")
    table = page_table(report)
    print(table)
    print(f"bench: wrote {out}")
    bench_common.book_or_not(update_book, page, START, END, table, report["machine"])
    worst, where = largest_region_difference(report)
    agrees = worst < AGREEMENT
    print(f"{'ok  ' if agrees else 'MISS'} every region within {100 * AGREEMENT:.0f}% of "
          f"Mitsuba's: the largest difference is {100 * worst:.2f}% ({where})")
    return 0 if agrees else 1
