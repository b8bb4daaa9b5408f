"""./course gpu-check's report and its row in the benchmarks page, from a made-up run
(the check itself runs end to end by hand: tools/gpu_check.sh, ten minutes)."""

from __future__ import annotations

from course_tools.cli import gpu_check


def made_up_report(renderer: str, newest_speed: float) -> dict:
    speed = {"samples_per_second": {"median": newest_speed}}
    return {
        "date": "2026-12-05 13:00 UTC", "seconds": 534.0, "repeat": 3,
        "phases": {"build": 60.0, "device": 2.0, "image checks": 300.0, "benches": 172.0},
        "device": {"backend": "egl device 1 (NVIDIA)", "renderer": renderer,
                   "gl_version": "4.6.0 NVIDIA 550", "egl_devices": ["egl device 0 (x)"],
                   "limits": {"max_compute_storage_blocks": 16,
                              "max_compute_texture_units": 32},
                   "loop_limit": "none"},
        "machine": {"cpu": "AMD EPYC", "cores": 2, "vectors": "AVX2",
                    "gl_renderer": renderer, "gl_version": "4.6", "mesa": None},
        "checks": {"total": {"passed": 900, "failed": 1, "skipped": 0},
                   "per_file": {"test_12_light_sampling": {"passed": 40, "failed": 1,
                                                           "skipped": 0}},
                   "failures": ["test_12_light_sampling::test_x (failed)"]},
        "benches": {"chapters": {"12_light_sampling": speed, "23_wavefront": speed},
                    "million": {"chapter": "21_tree_price",
                                "rays_per_second": {"median": 5e8}},
                    "kernels": {f"{scene}: {kernel}": {"samples_per_second":
                                                       {"median": 2.0 if kernel ==
                                                        "wavefront" else 1.0}}
                                for scene in gpu_check.KERNEL_SCENES
                                for kernel in ("megakernel", "wavefront")}},
    }


def test_the_report_says_what_a_first_gpu_run_needs_to_know():
    text = gpu_check.markdown(made_up_report("NVIDIA GeForce RTX 4070", 1e9))
    for said in ("egl device 1 (NVIDIA): `NVIDIA GeForce RTX 4070`", "16 storage blocks",
                 "loop limit none", "900 passed, 1 failed", "test_12_light_sampling::test_x",
                 "| **in all** | **8:54** (budget 10:00) |", "500,000,000 rays/s",
                 "sky_showcase: the wavefront at 2.00x"):
        assert said in text, said


def test_the_page_keeps_a_row_per_device(tmp_path, monkeypatch):
    page = tmp_path / "benchmarks.md"
    page.write_text(f"before\n{gpu_check.START}\n{gpu_check.END}\nafter\n")
    monkeypatch.setattr(gpu_check, "PAGE", page)
    monkeypatch.setattr(gpu_check, "ROOT", tmp_path)
    monkeypatch.setattr(gpu_check, "find_chapter", lambda n: {"12": "12_light_sampling"}[n])
    gpu_check.update_page(made_up_report("llvmpipe (LLVM 15.0.6, 256 bits)", 1e6))
    gpu_check.update_page(made_up_report("NVIDIA GeForce RTX 4070", 1e9))
    gpu_check.update_page(made_up_report("NVIDIA GeForce RTX 4070", 2e9))  # measured again
    text = page.read_text()
    rows = [line for line in text.splitlines() if line.startswith("| `")]
    assert len(rows) == 2, text
    assert "2,000,000,000" in text and "| 1,000,000,000 |" not in text.split("llvmpipe")[0]
    assert text.startswith("before\n") and text.endswith("after\n")
