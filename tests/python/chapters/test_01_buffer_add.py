"""Chapter 01: the GPU's sums must equal the CPU's, for sizes around the work-group
size (32) and a large one, on both headless backends; and the program must notice
when the shader is wrong."""

import json

import pytest

from conftest import BACKENDS, copy_shaders, run_chapter


@pytest.mark.windows
@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("count", [1, 31, 32, 33, 1_000_000])
def test_sums_match_the_cpu(backend, count):
    result = run_chapter("01", "--count", count, "--backend", backend, "--json")
    assert result.returncode == 0, result.stderr
    stats = json.loads(result.stdout)
    assert stats["count"] == count
    assert stats["mismatches"] == 0
    assert stats["work_groups"] == (count + 31) // 32
    assert "llvmpipe" in stats["renderer"] or stats["renderer"]


def test_report_is_readable():
    result = run_chapter("01", "--count", 33)
    assert result.returncode == 0
    assert "added 33 floats in 2 work groups of 32" in result.stdout
    assert "all correct" in result.stdout


def test_a_wrong_shader_is_caught(tmp_path):
    """If the shader forgets the constant, the CPU check must fail with exit code 1."""
    shaders = copy_shaders("01", tmp_path)
    source = shaders / "add.comp"
    text = source.read_text()
    assert "a[i] + b[i] + constant" in text
    source.write_text(text.replace("a[i] + b[i] + constant", "a[i] + b[i]"))
    result = run_chapter("01", "--count", 100, "--shader-dir", shaders)
    assert result.returncode == 1
    assert "100 of 100 sums are wrong" in result.stderr


def test_no_image_options():
    result = run_chapter("01", "--out", "x.png")
    assert result.returncode == 2
    assert "makes no image" in result.stderr
