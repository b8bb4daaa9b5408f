"""Grading a denoiser (tools/course_tools/grading/denoised_grading.py) on made-up
pictures whose truth is known: noisy runs of a scene with edges, filtered. The same
filter at other seeds passes, and so does another correct filter (a Gaussian for the
box); a filter that darkens, one that smears across an edge and one that reaches less
far (more noise left) fail, each for its own reason. The catalogue of real filters:
test_grading_statistics.py."""

import numpy as np
import pytest

from course_tools.grading import denoised_grading
from course_tools.grading.grading_specs import GradeTest, Sampling

SIZE = 64
TEST = GradeTest("made up", 1.0, [], "denoised", sampling=Sampling(16, 8, 16, 8))


class FakeOutcome:
    score = 0.0
    output = ""
    images = {}
    measurement = None


def scene():
    """Two walls of different light meeting at a vertical edge, a bright patch."""
    picture = np.full((SIZE, SIZE, 3), 0.3)
    picture[:, SIZE // 2:] = [0.6, 0.2, 0.1]
    picture[10:20, 40:50] += 1.0
    return picture


def noisy(truth, runs, rng, spp=8):
    shape = spp / 0.5 ** 2  # samples of standard deviation 0.5 of the truth, averaged
    return truth * rng.gamma(shape, 1.0 / shape, (runs, *truth.shape))


def blur(pictures, kernel, respect_edge=True):
    """A separable filter along rows and columns; with respect_edge, no tap crosses the
    vertical edge or leaves the picture (each side normalised on its own)."""
    side = np.where(np.arange(SIZE) < SIZE // 2, 0, 1)
    reach = len(kernel) // 2
    out = np.zeros_like(pictures)
    weights = np.zeros(pictures.shape[:3] + (1,))
    for dy in range(-reach, reach + 1):
        for dx in range(-reach, reach + 1):
            w = kernel[dy + reach] * kernel[dx + reach]
            shifted = np.roll(pictures, (dy, dx), axis=(1, 2))
            valid = np.ones((SIZE, SIZE))
            rows, columns = np.arange(SIZE) - dy, np.arange(SIZE) - dx
            valid *= ((rows >= 0) & (rows < SIZE))[:, None]
            valid *= ((columns >= 0) & (columns < SIZE))[None, :]
            if respect_edge:
                valid *= side[None, :] == side[np.clip(columns, 0, SIZE - 1)][None, :]
            out += w * valid[None, ..., None] * shifted
            weights += w * valid[None, ..., None]
    return out / weights


BOX = np.ones(7)
GAUSSIAN = np.exp(-0.5 * (np.arange(-3, 4) / 2.0) ** 2)


def graded(tmp_path, runs, solution_runs):
    return denoised_grading.judge(TEST, FakeOutcome(), tmp_path, runs, solution_runs)


@pytest.fixture
def solution_runs():
    return blur(noisy(scene(), 16, np.random.default_rng(1)), BOX)


@pytest.mark.parametrize("seed", range(5))
def test_the_same_filter_at_other_seeds_passes(tmp_path, solution_runs, seed):
    runs = blur(noisy(scene(), 16, np.random.default_rng(100 + seed)), BOX)
    outcome = graded(tmp_path, runs, solution_runs)
    assert outcome.score == 1.0, outcome.output
    assert (tmp_path / "made_up_error.png").exists()


def test_another_correct_filter_passes(tmp_path, solution_runs):
    runs = blur(noisy(scene(), 16, np.random.default_rng(2)), GAUSSIAN)
    outcome = graded(tmp_path, runs, solution_runs)
    assert outcome.score == 1.0, outcome.output


@pytest.mark.parametrize("name,filtered,message", [
    ("darkened by 3%", lambda p: 0.97 * blur(p, BOX), "other light"),
    ("smeared across the edge", lambda p: blur(p, BOX, respect_edge=False), "other light"),
    ("reaching less far", lambda p: blur(p, np.ones(3)), "noise"),
])
def test_wrong_filters_fail(tmp_path, solution_runs, name, filtered, message):
    runs = filtered(noisy(scene(), 16, np.random.default_rng(3)))
    outcome = graded(tmp_path, runs, solution_runs)
    assert outcome.score == 0.0 and message in outcome.output, (name, outcome.output)


def test_broken_and_seedless_runs_fail(tmp_path, solution_runs):
    runs = blur(noisy(scene(), 16, np.random.default_rng(4)), BOX)
    runs[3, 5, 5, 0] = np.nan
    assert "NaN" in graded(tmp_path, runs, solution_runs).output
    one = blur(noisy(scene(), 1, np.random.default_rng(5)), BOX)
    outcome = graded(tmp_path, np.repeat(one, 16, axis=0), solution_runs)
    assert outcome.score == 0.0 and "seed" in outcome.output
