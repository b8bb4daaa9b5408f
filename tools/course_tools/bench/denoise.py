"""./course bench denoise: chapter 28's filter against the raw picture and against Intel
Open Image Denoise, on four scenes, and what the filter costs in samples a pixel.

Quality: for each scene (the Cornell box, the teapot, glass with caustics, the textured
room through a lens) at SIZE x SIZE, the raw picture, ours (--denoise atrous) and OIDN
(pyoidn, on the same raw colour, albedo and normal) at 4, 8 and 16 samples a pixel, and
the raw picture at 64, each against Mitsuba 3 at REFERENCE_SPP samples (kept once made),
by the issue's relative MSE, mean((x - ref)^2 / (ref^2 + 0.01)), over SEEDS seeds.
These do not depend on how busy the machine is.

Cost: the Cornell box at COST_WIDTH x COST_HEIGHT, 8 samples a pixel; the chapter
reports the filter's GPU time (denoise_ms) and the whole render's (gpu_ms): the filter
costs denoise_ms / ((gpu_ms - denoise_ms) / 8) samples of the path tracer. OIDN's time
is the CPU time of one pyoidn.denoise call on the same picture. Each the median of
--repeat runs. Writes build/bench/denoise.json and prints the tables, and draws the
error against samples and against time (in samples of the path tracer, the filter's or
OIDN's cost added) as build/bench/denoise_error.png; writes the tables into
book/docs/benchmarks.md and chapter 28's page, and the figure into book/docs/figures/,
only with --update-book."""

from __future__ import annotations

import json
import shutil
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from course_tools.bench import common as bench_common
from course_tools.paths import ROOT

CHAPTERS = ROOT / "book" / "docs" / "chapters"
MARKERS = ("<!-- bench-denoise:start -->", "<!-- bench-denoise:end -->")
PAGES = {"benchmarks": (ROOT / "book" / "docs" / "benchmarks.md", *MARKERS),
         "28": (CHAPTERS / "28_denoising.md", *MARKERS)}
OUT = ROOT / "build" / "bench"
FIGURE = ROOT / "book" / "docs" / "figures" / "denoise_error.png"
SCENES = {"cornell_box": "Cornell box", "cornell_teapot": "teapot",
          "cornell_glass": "glass (caustics)", "lens_textures": "textures, through a lens"}
SAMPLES = (4, 8, 16)
RAW_BAR = 64
REFERENCE_SPP = 16384
COST_WIDTH, COST_HEIGHT = 400, 225


@dataclass
class Settings:
    size: int = 160
    seeds: int = 2
    repeat: int = 3


def render(binary: Path, folder: Path, scene: str, width: int, height: int, spp: int,
           denoise: str, seed: int = 1, aux: bool = False) -> tuple[dict, Path]:
    out = folder / f"{scene}_{width}x{height}_{denoise}_{spp}_{seed}"
    stats = bench_common.program_stats(
        [binary, "--headless", "--scene", scene, "--width", width, "--height", height,
         "--spp", spp, "--denoise", denoise, "--seed", seed, "--out", f"{out}.pfm", "--json",
         *(["--aux-out", out] if aux else [])], "denoise")
    return stats, out


def oidn(prefix: Path) -> tuple[np.ndarray, float]:
    """OIDN's picture from a raw render's colour, albedo and normal, and its CPU time."""
    import pyoidn
    from python_prototypes.pfm import read_pfm
    noisy, albedo, normal = (read_pfm(f"{prefix}{suffix}.pfm").astype(np.float32)
                             for suffix in ("", "_albedo", "_normal"))
    start = time.process_time()
    cleaned = pyoidn.denoise(noisy, albedo, normal * 2.0 - 1.0, hdr=True)
    return np.asarray(cleaned, dtype=np.float64), time.process_time() - start


def quality(binary: Path, meshes: Path, settings: Settings, folder: Path) -> list:
    from course_tools import mitsuba_cache
    from python_prototypes import scene_io
    from python_prototypes.denoise import relative_mse
    from python_prototypes.pfm import read_pfm
    rows = []
    for scene, name in SCENES.items():
        loaded = scene_io.load_scene(str(ROOT / "assets" / "scenes" / f"{scene}.scene"),
                                     [str(meshes.parent)])
        print(f"bench denoise: {name}: Mitsuba at {REFERENCE_SPP} spp (kept once made) ...",
              flush=True)
        reference = mitsuba_cache.kept_render(loaded, settings.size, settings.size,
                                               REFERENCE_SPP, 6, variant="llvm_ad_rgb")
        seeds = range(1, settings.seeds + 1)
        row = {"scene": scene, "name": name}
        for spp in SAMPLES:
            raw, ours, theirs = [], [], []
            for seed in seeds:
                _, prefix = render(binary, folder, scene, settings.size, settings.size, spp,
                                   "none", seed, aux=True)
                raw.append(relative_mse(read_pfm(f"{prefix}.pfm"), reference))
                theirs.append(relative_mse(oidn(prefix)[0], reference))
                _, prefix = render(binary, folder, scene, settings.size, settings.size, spp,
                                   "atrous", seed)
                ours.append(relative_mse(read_pfm(f"{prefix}.pfm"), reference))
            row[str(spp)] = {"raw": float(np.mean(raw)), "ours": float(np.mean(ours)),
                             "oidn": float(np.mean(theirs))}  # keyed as JSON reads back
        _, prefix = render(binary, folder, scene, settings.size, settings.size, RAW_BAR,
                           "none")
        row["raw_bar"] = relative_mse(read_pfm(f"{prefix}.pfm"), reference)
        rows.append(row)
    return rows


def cost(binary: Path, settings: Settings, folder: Path) -> tuple[dict, dict]:
    """The filter's cost in samples a pixel, and OIDN's time, at COST_WIDTH x
    COST_HEIGHT: the median of settings.repeat runs (after one untimed)."""
    arguments = (binary, folder, "cornell_box", COST_WIDTH, COST_HEIGHT, 8, "atrous")
    first, _ = render(*arguments)
    runs = {"denoise_ms": [], "sample_ms": [], "oidn_ms": []}
    for _ in range(settings.repeat):
        stats, _ = render(*arguments)
        runs["denoise_ms"].append(stats["denoise_ms"])
        runs["sample_ms"].append((stats["gpu_ms"] - stats["denoise_ms"]) / 8)
        _, prefix = render(binary, folder, "cornell_box", COST_WIDTH, COST_HEIGHT, 8, "none",
                           aux=True)
        runs["oidn_ms"].append(1000.0 * oidn(prefix)[1])
    summary = {key: bench_common.summarise(values) for key, values in runs.items()}
    summary["samples"] = bench_common.summarise(
        [d / s for d, s in zip(runs["denoise_ms"], runs["sample_ms"])])
    return summary, first


def bench(binary: Path, meshes: Path, settings: Settings, folder: Path = OUT / "denoise"
          ) -> dict:
    folder.mkdir(parents=True, exist_ok=True)
    rows = quality(binary, meshes, settings, folder)
    watch = bench_common.QuietWatch()  # the timings only: the errors do not mind
    costs, first = cost(binary, settings, folder)
    return {"date": bench_common.today(), "machine": bench_common.describe_machine(first),
            "settings": vars(settings), "reference_spp": REFERENCE_SPP, "rows": rows,
            "cost": costs, "quiet": watch.finish()}


def page_table(report: dict) -> str:
    s, c = report["settings"], report["cost"]
    lines = [f"Measured {report['date']} on "
             f"{bench_common.machine_words(report['machine'])}. Relative MSE against "
             f"Mitsuba 3 at {report['reference_spp']:,} spp, {s['size']}² pixels, the mean "
             f"of {s['seeds']} seeds; OIDN through pyoidn on the same raw colour, albedo and "
             "normal.", "",
             "| scene | spp | raw | ours | OIDN | ours ÷ OIDN | raw at 64 spp |",
             "| --- | ---: | ---: | ---: | ---: | ---: | ---: |"]
    for row in report["rows"]:
        for spp in SAMPLES:
            cell = row[str(spp)]
            first = spp == SAMPLES[0]
            lines.append(f"| {row['name'] if first else ''} | {spp} | {cell['raw']:.5f} "
                         f"| {cell['ours']:.5f} | {cell['oidn']:.5f} "
                         f"| {cell['ours'] / cell['oidn']:.2f} "
                         f"| {format(row['raw_bar'], '.5f') if first else ''} |")
    lines += ["", f"The filter at {COST_WIDTH}×{COST_HEIGHT} (the Cornell box, 8 spp) takes "
              f"{c['denoise_ms']['median']:.1f} ms of GPU time, as much as "
              f"**{c['samples']['median']:.2f} samples a pixel** of the path tracer "
              f"({c['sample_ms']['median']:.1f} ms each); OIDN takes "
              f"{c['oidn_ms']['median']:.0f} ms of CPU time. Medians of {s['repeat']} runs. "
              f"{bench_common.quiet_words(report['quiet'])}"]
    return "\n".join(lines)


def draw_figure(report: dict, path: Path):
    """Per scene, the relative MSE of raw, ours and OIDN against samples a pixel (top)
    and against time (bottom), time in samples of the path tracer: n samples cost n, the
    filter and OIDN their measured cost more (report['cost']: at 400 x 225, in
    proportion to the pixels as a sample is). The raw picture at 64 samples is the
    dashed line."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    cost = report["cost"]
    extra = {"raw": 0.0, "ours": cost["samples"]["median"],
             "oidn": cost["oidn_ms"]["median"] / cost["sample_ms"]["median"]}
    styles = {"raw": ("raw", "0.5", "o"), "ours": ("ours (a-trous)", "tab:blue", "s"),
              "oidn": ("OIDN", "tab:orange", "^")}
    rows = report["rows"]
    figure, axes = plt.subplots(2, len(rows), figsize=(3.2 * len(rows), 5.6),
                                squeeze=False)
    spps = [int(s) for s in SAMPLES]
    for column, row in enumerate(rows):
        for line, (top, bottom) in enumerate(zip(axes[0], axes[1])):
            if line != column:
                continue
            for method, (label, colour, marker) in styles.items():
                errors = [row[str(n)][method] for n in spps]
                top.plot(spps, errors, marker=marker, color=colour, label=label)
                bottom.plot([n + extra[method] for n in spps], errors, marker=marker,
                            color=colour, label=label)
            for panel in (top, bottom):
                panel.axhline(row["raw_bar"], color="0.5", linestyle="--", linewidth=1)
                panel.set_xscale("log", base=2)
                panel.set_xticks(spps, [str(n) for n in spps])
                panel.set_yscale("log")
                panel.grid(True, which="major", alpha=0.3)
            top.set_title(row["name"], fontsize=10)
            top.set_xlabel("samples a pixel")
            bottom.set_xlabel("time, in samples of the path tracer")
    axes[0][0].set_ylabel("relative MSE")
    axes[1][0].set_ylabel("relative MSE")
    axes[0][0].legend(fontsize=8)
    figure.suptitle(f"{report['machine']['cpu']} ({report['machine']['vectors']}), "
                    f"{report['settings']['size']}², against Mitsuba at "
                    f"{report['reference_spp']} spp; dashed: raw at {RAW_BAR} spp",
                    fontsize=9)
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    plt.close(figure)


def publish(report: dict, update_book: bool = False, pages: dict = PAGES,
            out_folder: Path = OUT, figure: Path = FIGURE):
    """The report in out_folder (denoise.json) with its figure, the table printed, and
    both written into the book (the benchmarks page, chapter 28's, the figure) only with
    update_book."""
    table = page_table(report)
    out = out_folder / "denoise.json"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(report, indent=2) + "\n")
    drawn = out_folder / figure.name
    draw_figure(report, drawn)
    print(table)
    print(f"bench: wrote {out} and {drawn}")
    for page, start, end in pages.values():
        bench_common.book_or_not(update_book, page, start, end, table, report["machine"])
    if update_book:
        figure.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(drawn, figure)
        print(f"bench: wrote {figure}")


def main(binary: Path, meshes: Path, settings: Settings, update_book: bool = False,
         pages: dict = PAGES, out_folder: Path = OUT) -> int:
    publish(bench(binary, meshes, settings, out_folder / "denoise"), update_book, pages,
            out_folder)
    return 0
