"""./course bench: chapter 12 (NEE + MIS) against Mitsuba 3 on the Cornell box, in one run.

Same scene (assets/scenes/cornell_box.scene, which is mitsuba.cornell_box()), same
resolution, samples per pixel and depth (ours --depth N = Mitsuba max_depth N + 1), our
NEE + MIS path tracer on llvmpipe against Mitsuba's `path` integrator in its scalar_rgb
and llvm_ad_rgb variants. Prints samples/s, rays/s (ours: counted by the shader), the
speed ratios and each region's mean against Mitsuba's (the 1% check), then writes
build/bench/bench.json and the table in book/docs/benchmarks.md."""

from __future__ import annotations

import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python_prototypes"))
PAGE = ROOT / "book" / "docs" / "benchmarks.md"
START, END = "<!-- bench:start -->", "<!-- bench:end -->"


def cpu_model() -> str:
    for line in Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith("model name"):
            return line.split(":", 1)[1].strip()
    return platform.processor() or "unknown"


def read_pfm(path: Path) -> np.ndarray:
    import mitsuba_reference
    return mitsuba_reference.read_pfm(path)[..., :3]


def run_ours(binary: Path, scene: Path, size: int, spp: int, depth: int):
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder) / "ours.pfm"
        result = subprocess.run([str(binary), "--headless", "--scene", str(scene),
                                 "--width", str(size), "--height", str(size), "--spp",
                                 str(spp), "--depth", str(depth), "--estimator", "mis",
                                 "--out", str(out), "--json"],
                                capture_output=True, text=True, check=True)
        stats = json.loads(result.stdout.strip().splitlines()[-1])
        return read_pfm(out), stats


def compare(scene, ours: np.ndarray, theirs: np.ndarray) -> dict:
    """Per region: our mean, Mitsuba's, relative difference and its standard error."""
    import mitsuba_reference
    masks = mitsuba_reference.region_masks(scene, ours.shape[1], ours.shape[0])
    mine = mitsuba_reference.region_means(ours, masks)
    reference = mitsuba_reference.region_means(theirs, masks)
    errors = mitsuba_reference.region_standard_errors(ours, theirs, masks)
    rows = {}
    for name, mask in masks.items():
        if mask.sum() < 20:
            continue
        # The relative difference of the regions' brightness (mean over RGB).
        a, b, e = mine[name].mean(), reference[name].mean(), errors[name].mean()
        rows[name] = {"pixels": int(mask.sum()), "ours": float(a), "mitsuba": float(b),
                      "relative": float(a / b - 1), "relative_error": float(e / b)}
    return rows


def page_table(report: dict) -> str:
    machine = report["machine"]
    lines = [f"Measured {report['date']} on {machine['cpu']} ({machine['cores']} cores), "
             f"our renderer on `{machine['gl_renderer']}`; Cornell box "
             f"{report['size']}², {report['spp']} spp, depth {report['depth']} "
             "(Mitsuba `max_depth` "
             f"{report['depth'] + 1}).", "",
             "| renderer | seconds | samples/s | rays/s | speed ÷ ours |",
             "| --- | ---: | ---: | ---: | ---: |"]
    ours = report["ours"]
    lines.append(f"| ours, GLSL on llvmpipe, NEE + MIS | {ours['seconds']:.1f} | "
                 f"{ours['samples_per_second']:,.0f} | {ours['rays_per_second']:,.0f} | 1 |")
    for variant, row in report["mitsuba"].items():
        lines.append(f"| Mitsuba 3.9.1 `{variant}` | {row['seconds']:.1f} | "
                     f"{row['samples_per_second']:,.0f} | — | "
                     f"{row['samples_per_second'] / ours['samples_per_second']:.2f}× |")
    lines += ["", "Each region's mean (RGB averaged) against Mitsuba `scalar_rgb`:", "",
              "| region | pixels | ours | Mitsuba | difference | standard error |",
              "| --- | ---: | ---: | ---: | ---: | ---: |"]
    for name, row in report["regions"].items():
        lines.append(f"| {name} | {row['pixels']} | {row['ours']:.4f} | "
                     f"{row['mitsuba']:.4f} | {100 * row['relative']:+.2f}% | "
                     f"{100 * row['relative_error']:.2f}% |")
    return "\n".join(lines)


def bench(binary: Path, size: int = 256, spp: int = 128, depth: int = 6) -> dict:
    import mitsuba_reference
    import scene_io
    scene_path = ROOT / "assets" / "scenes" / "cornell_box.scene"
    scene = scene_io.load_scene(str(scene_path))
    print(f"ours: {size}x{size}, {spp} spp, depth {depth} ...", flush=True)
    ours, stats = run_ours(binary, scene_path, size, spp, depth)
    report = {"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
              "size": size, "spp": spp, "depth": depth,
              "machine": {"cpu": cpu_model(), "cores": os.cpu_count(),
                          "gl_renderer": stats["renderer"]},
              "ours": {"seconds": stats["wall_ms"] / 1000, "rays": stats["rays"],
                       "samples_per_second": stats["samples_per_second"],
                       "rays_per_second": stats["rays_per_second"]},
              "mitsuba": {}}
    reference = None
    for variant in ("scalar_rgb", "llvm_ad_rgb"):
        print(f"mitsuba {variant} ...", flush=True)
        try:
            image, mitsuba_stats = mitsuba_reference.render_mitsuba(
                scene, size, size, spp, depth, seed=0, variant=variant)
        except Exception as error:  # a missing libLLVM: report it, keep the rest
            print(f"  skipped: {error}")
            continue
        report["mitsuba"][variant] = {"seconds": mitsuba_stats["seconds"],
                                      "samples_per_second": mitsuba_stats["samples_per_second"]}
        if reference is None:
            reference = np.asarray(image)[..., :3]
    report["regions"] = compare(scene, ours, reference)
    return report


def main(binary: Path, size: int, spp: int, depth: int) -> int:
    report = bench(binary, size, spp, depth)
    out = ROOT / "build" / "bench" / "bench.json"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(report, indent=2) + "\n")
    table = page_table(report)
    print(table)
    text = PAGE.read_text()
    before, rest = text.split(START, 1)
    _, after = rest.split(END, 1)
    PAGE.write_text(f"{before}{START}\n{table}\n{END}{after}")
    worst = max(abs(row["relative"]) for row in report["regions"].values())
    print(f"wrote {out} and {PAGE}; largest region difference {100 * worst:.2f}%")
    return 0 if worst < 0.01 else 1
