"""Statistical grading (tools/course_tools/grading/grading_statistics.py): the z-test on
made-up pictures whose truth is known, its guards, and the catalogues of
grading_catalogue graded for real: every correct-but-different implementation scores at
least 90% and is diagnosed as no mistake, every plausible wrong one at most half and is
diagnosed as itself (from seeds its signature was not made from), every held-out one
(a catalogued mistake written differently) as the mistake it makes.

The catalogues grade each variant with grader.grade, a chapter's two at a time (the
machine's two cores), after the chapter's mistake signatures (grader.prepare_signatures),
and write the scores, diagnoses and times to build/test-artifacts/grading-catalogue-NN.txt
and .json (the instructors page's tables, ./course test --update-book:
tools/course_tools/cli/measured_pages.py)."""

import json
import math
import os
import re
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

from conftest import ROOT, read_pfm, run_chapter

from course_tools.grading import diagnosis, grader
from course_tools.grading import grading_statistics as statistics
import grading_catalogue
from course_tools.grading.grading_specs import SPECS, GradeTest, Sampling

BUILD = ROOT / "build"
ARTIFACTS = BUILD / "test-artifacts"


# ---------------------------------------------------------------- made-up pictures

def noisy_runs(truth, runs, spp, rng, scale=0.5, tail=0.0):
    """`runs` pictures, each the mean of `spp` samples of truth times noise of mean 1 and
    standard deviation `scale`; with `tail`, that share of the samples is 50 x truth
    brighter (and all of them darker by as much on average: a path tracer's fireflies,
    unbiased)."""
    if not tail:  # gamma samples (positive, as light is): their mean, drawn at once
        shape = spp / scale ** 2
        return truth * rng.gamma(shape, 1.0 / shape, (runs, *truth.shape))
    samples = truth * rng.gamma(1 / scale ** 2, scale ** 2, (runs, spp, *truth.shape))
    rare = rng.random((runs, spp, *truth.shape)) < tail
    return (samples + 50.0 * truth * (rare - tail)).mean(axis=1)


def scene(height=32, width=32):
    """A picture with structure: a gradient, a bright square, a dark corner."""
    y, x = np.mgrid[0:height, 0:width] / max(height, width)
    picture = np.stack([0.2 + 0.5 * x, 0.3 + 0.2 * y, 0.1 + 0.1 * x * y], axis=-1)
    picture[8:14, 18:26] += 2.0
    picture[:4, :4] = 0.01
    return picture


def test_correct_pictures_pass_at_every_seed():
    """Sixty draws of an unbiased estimator with heavy tails: none is rejected (the
    family-wise level is 1e-4 per test)."""
    truth = scene()
    for seed in range(60):
        rng = np.random.default_rng(seed)
        runs = noisy_runs(truth, 8, 64, rng, tail=0.001)
        reference = noisy_runs(truth, 4, 512, rng, tail=0.001)
        result = statistics.compare(runs, reference, noisy_runs(truth, 8, 64, rng, tail=0.001))
        assert result.passed, (seed, np.abs(result.z).max())


@pytest.mark.parametrize("where,bias,found_at", [
    ("everywhere", 1.02, 1),           # 2% too bright: seen over the whole picture
    ("one block", 1.25, 8),            # 25% in a 4 x 4 block: seen in that block
    ("one channel", 0.97, None),       # the blue channel 3% dark
])
def test_biased_pictures_fail_where_the_bias_is(where, bias, found_at):
    rng = np.random.default_rng(7)
    truth = scene()
    wrong = truth.copy()
    if where == "everywhere":
        wrong *= bias
    elif where == "one block":
        wrong[20:24, 4:8] *= bias
    else:
        wrong[..., 2] *= bias
    result = statistics.compare(noisy_runs(wrong, 8, 64, rng, scale=0.3),
                                noisy_runs(truth, 4, 2048, rng, scale=0.3),
                                noisy_runs(truth, 8, 64, rng, scale=0.3))
    assert not result.passed
    worst = result.regions[int(np.argmax(np.abs(result.z)))]
    if found_at:
        assert worst.level == found_at
    if where == "one channel":
        assert {r.channel for r, bad in zip(result.regions, result.rejected) if bad} == {2}


def test_a_picture_without_noise_must_be_right_to_rounding():
    """A deterministic picture (its own variance zero) is allowed only the reference's
    error and float rounding: exactly right passes, 0.5% off fails."""
    rng = np.random.default_rng(3)
    truth = scene()
    reference = noisy_runs(truth, 4, 100_000, rng, scale=0.1)
    exact = np.repeat(truth[None].astype(np.float32).astype(np.float64), 8, axis=0)
    assert statistics.compare(exact, reference).passed
    result = statistics.compare(exact * 1.005, reference)
    assert not result.passed and result.variance_ratio == 1.0


def test_region_errors_hold_when_pixels_are_correlated():
    """Every pixel of a run shares one random offset (as with one random stream for the
    whole picture): the pooled per-pixel error alone would be far too small; the spread
    of the region means between runs keeps the test honest."""
    rng = np.random.default_rng(11)
    truth = scene()
    def correlated(runs, spp):
        shared = rng.standard_normal((runs, 1, 1, 1)) * 0.2 / math.sqrt(spp)
        return noisy_runs(truth, runs, spp, rng, scale=0.05) + shared * truth.mean()
    for _ in range(20):
        assert statistics.compare(correlated(8, 64), correlated(4, 2048)).passed


def test_holm_matches_its_definition():
    rng = np.random.default_rng(5)
    for _ in range(200):
        p = rng.random(12) ** 4
        rejected = statistics.holm(p, 0.05)
        order = np.argsort(p)
        expected = np.zeros(12, dtype=bool)
        for rank, index in enumerate(order):
            if p[index] > 0.05 / (12 - rank):
                break
            expected[index] = True
        assert (rejected == expected).all()
    assert statistics.normal_quantile_two_sided(0.05) == pytest.approx(1.959964, abs=1e-5)
    assert math.erfc(statistics.normal_quantile_two_sided(1e-7) / math.sqrt(2)) == \
        pytest.approx(1e-7, rel=1e-6)


def test_block_levels_keep_enough_pixels():
    assert statistics.block_levels(32, 32) == [1, 2, 4, 8]
    assert statistics.block_levels(24, 48) == [1, 2, 4, 8]  # 8x8 blocks: 3 x 6 pixels
    assert statistics.block_levels(12, 12) == [1, 2]        # 4x4 blocks: 3 x 3
    assert statistics.block_levels(3, 3) == [1]


# ---------------------------------------------------------------- guards

class FakeOutcome:
    score = 0.0
    output = ""
    images = {}


STATISTICAL = GradeTest("made up", 1.0, [], "statistical", sampling=Sampling(8, 16, 4, 256))


@pytest.mark.parametrize("damage,message", [
    (lambda runs: runs.__setitem__((3, 5, 5, 0), np.nan), "NaN or infinite"),
    (lambda runs: runs.__setitem__((0, 1, 2, 1), np.inf), "NaN or infinite"),
    (lambda runs: runs.__setitem__((2, 9, 9, 2), -0.5), "negative"),
    (lambda runs: runs.__imul__(0.0), "region means differ"),  # black
])
def test_broken_pictures_score_nothing(tmp_path, damage, message):
    rng = np.random.default_rng(1)
    truth = scene()
    runs = noisy_runs(truth, 8, 16, rng)
    damage(runs)
    outcome = statistics._grade_statistical(
        STATISTICAL, FakeOutcome(), tmp_path, runs, noisy_runs(truth, 4, 256, rng),
        noisy_runs(truth, 8, 16, rng))
    assert outcome.score == 0.0 and message in outcome.output, outcome.output


def test_a_much_noisier_picture_fails_although_unbiased(tmp_path):
    """Without this guard, adding noise would pass any z-test."""
    rng = np.random.default_rng(2)
    truth = scene()
    reference = noisy_runs(truth, 4, 256, rng)
    fair = noisy_runs(truth, 8, 16, rng)
    outcome = statistics._grade_statistical(STATISTICAL, FakeOutcome(), tmp_path,
                                            noisy_runs(truth, 8, 16, rng, scale=1.5),
                                            reference, fair)
    assert outcome.score == 0.0 and "as noisy as the solution's" in outcome.output
    outcome = statistics._grade_statistical(STATISTICAL, FakeOutcome(), tmp_path,
                                            noisy_runs(truth, 8, 16, rng, scale=0.9),
                                            reference, fair)
    assert outcome.score == 1.0, outcome.output  # 3.2 x the variance: allowed
    assert (tmp_path / "made_up_error.png").exists()


def test_runs_that_ignore_the_seed_are_named(tmp_path):
    rng = np.random.default_rng(4)
    truth = scene()
    one = noisy_runs(truth, 1, 16, rng)
    outcome = statistics._grade_statistical(STATISTICAL, FakeOutcome(), tmp_path,
                                            np.repeat(one, 8, axis=0),
                                            noisy_runs(truth, 4, 256, rng),
                                            noisy_runs(truth, 8, 16, rng))
    assert "ignores --seed" in outcome.output and outcome.score == 0.0


def test_outputs_are_read_without_following_links(tmp_path):
    secret = tmp_path / "secret.pfm"
    secret.write_bytes(b"PF\n1 1\n-1.0\n" + np.zeros(3, "<f4").tobytes())
    (tmp_path / "out.pfm").symlink_to(secret)
    with pytest.raises(ValueError, match="link"):
        statistics.read_output(tmp_path / "out.pfm")
    with pytest.raises(ValueError, match="not an RGB PFM"):
        statistics.parse_pfm(b"P6\n1 1\n255\n\0\0\0")
    with pytest.raises(ValueError, match="not a whole PFM image"):
        statistics.parse_pfm(b"PF\n4 4\n-1.0\n" + bytes(12))


def test_pfm_reader_agrees_with_the_chapters_writer(tmp_path):
    out = tmp_path / "image.pfm"
    result = run_chapter("11", "--headless", "--width", "13", "--height", "7", "--spp", "2",
                         "--out", str(out))
    assert result.returncode == 0, result.stderr
    assert np.array_equal(statistics.read_pfm(out), read_pfm(out))


# ---------------------------------------------------------------- --view cost

def heat(x):
    """path.comp's heat(): the heat map the cost view draws, written again here."""
    colours = statistics.HEAT_COLOURS
    x = np.clip(x, 0.0, 1.0)[..., None] * 3.0
    return np.where(x < 1.0, colours[0] + (colours[1] - colours[0]) * x,
                    np.where(x < 2.0, colours[1] + (colours[2] - colours[1]) * (x - 1.0),
                             colours[2] + (colours[3] - colours[2]) * (x - 2.0)))


def test_cost_heat_map_constants_are_the_shaders():
    source = (ROOT / "shaders" / "13_bvh" / "path.comp").read_text()
    scale = re.search(r"const float COST_SCALE = ([\d.]+);", source)
    assert float(scale.group(1)) == statistics.COST_SCALE
    for name, colour in zip(("blue", "cyan", "yellow", "red"), statistics.HEAT_COLOURS):
        found = re.search(rf"{name} = vec3\(([^)]*)\)", source)
        assert [float(v) for v in found.group(1).split(",")] == pytest.approx(list(colour))


def test_cost_decodes_every_step_count():
    steps = np.arange(0, 61, dtype=np.float64).reshape(1, -1)
    decoded, off = statistics.decode_cost(heat(steps / statistics.COST_SCALE))
    assert np.allclose(decoded, steps, atol=1e-6) and off < 1e-9
    _, off = statistics.decode_cost(np.full((1, 1, 3), 0.5))
    assert off > 0.1  # grey is not on the map


def test_solution_cost_view_decodes_to_whole_steps(tmp_path):
    out = tmp_path / "cost.pfm"
    result = run_chapter("13", "--headless", "--width", "32", "--height", "32", "--view",
                         "cost", "--out", str(out))
    assert result.returncode == 0, result.stderr
    steps, off = statistics.decode_cost(read_pfm(out))
    assert off < 1e-3
    inside = steps < statistics.COST_SCALE - 0.5
    assert np.allclose(steps[inside], np.round(steps[inside]), atol=1e-3)
    assert steps.min() >= 1


# ---------------------------------------------------------------- the catalogues

CATALOGUES = {number: variants[0].chapter
              for number, variants in sorted(grading_catalogue.CATALOGUE.items())}
VARIANTS = [v for number, chapter in CATALOGUES.items()
            for v in (grading_catalogue.solution(chapter), *grading_catalogue.CATALOGUE[number])]


def test_the_catalogues_cover_every_statistical_chapter():
    """Every chapter graded by statistics or by its tree has a catalogue, and at least
    four chapters graded by their pictures alone (for the diagnosis)."""
    statistical = {n for n, tests in SPECS.items()
                   if any(t.kind in statistics.KINDS for t in tests)}
    assert statistical <= set(CATALOGUES)
    assert len(set(CATALOGUES) - statistical) >= 4
    for number in CATALOGUES:
        kinds = [v.correct for v in grading_catalogue.CATALOGUE[number] if not v.held_out]
        assert kinds.count(True) >= 3 and kinds.count(False) >= 4, number
    assert len(grading_catalogue.CATALOGUE["12"]) >= 12


def grade_variant(variant, folder: Path) -> tuple[dict, float, dict]:
    """Grades a variant as a student's submission. Its runs are kept (grader.KeptRuns):
    a variant whose files, solution, build and GL are those of an earlier suite run is
    not rendered again, but its pictures are graded anew. The counts hold the runs
    replayed and made, and the diagnosis of its measurements whether or not it failed
    (a correct variant must be diagnosed as nothing even so)."""
    started = time.monotonic()
    submission = grading_catalogue.apply(variant, ROOT, folder / "submission")
    counts, measured = {}, {}
    results = grader.grade(ROOT, BUILD, variant.chapter, submission, folder / "graded",
                           keep_runs=True, kept_counts=counts, measured=measured)
    signatures = grader.load_signatures(BUILD, variant.chapter)
    diagnosing = time.monotonic()
    counts["diagnosis"] = diagnosis.diagnose(measured, signatures)
    counts["diagnosis seconds"] = time.monotonic() - diagnosing
    return results, time.monotonic() - started, counts


GRADED: dict[str, dict] = {}  # chapter -> {variant: (results, seconds, counts)}


@pytest.fixture
def catalogue_results(request, tmp_path_factory):
    """Grades every variant of the requested variant's chapter that pytest selected, two
    at a time, once per chapter: the solution's references first (kept: the grader's
    build/grading and the per-user reference cache), then the submissions. A chapter's
    variants run in one worker (conftest.work_group), the chapters spread over them."""
    chapter = request.node.callspec.params["variant"].chapter
    if chapter not in GRADED:
        selected = [item.callspec.params["variant"] for item in request.session.items
                    if getattr(item, "callspec", None) and "variant" in item.callspec.params
                    and item.originalname == "test_catalogue_variant"
                    and item.callspec.params["variant"].chapter == chapter]
        grader.prepare_references(ROOT, BUILD, chapter)
        started = time.monotonic()
        grader.prepare_signatures(ROOT, BUILD, chapter)
        signing = time.monotonic() - started
        base = tmp_path_factory.mktemp(f"catalogue-{chapter[:2]}")
        started = time.monotonic()
        with ThreadPoolExecutor(max_workers=min(2, os.cpu_count() or 1)) as pool:
            GRADED[chapter] = dict(zip(selected, pool.map(
                lambda v: grade_variant(v, base / v.slug), selected)))
        write_summary(chapter, GRADED[chapter], time.monotonic() - started, signing)
    return GRADED[chapter]


def diagnosed(counts: dict) -> list[str]:
    found = counts["diagnosis"]
    return [m["name"] for m in found["matches"]] if found else []


def as_meant(variant, counts: dict) -> bool:
    """Diagnosed as the mistake it makes, or with mistakes declared to have its effect."""
    names = diagnosed(counts)
    meant = variant.held_out or variant.name
    effects = {v.name: v.same_effect for v in grading_catalogue.CATALOGUE[variant.chapter[:2]]
               if v.same_effect}
    return bool(names) and meant in names and \
        all(diagnosis.related(name, meant, effects) for name in names)


def write_summary(chapter: str, graded: dict, seconds: float, signing: float):
    """One file per chapter: each variant's share of the points, each test's score,
    what the diagnosis named."""
    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    replayed = sum(counts.get("replayed", 0) for _, _, counts in graded.values())
    made = sum(counts.get("made", 0) for _, _, counts in graded.values())
    signatures = grader.load_signatures(BUILD, chapter) or {}
    random = any(t.kind in statistics.RANDOM_KINDS for t in SPECS[chapter[:2]])
    threshold = (f"threshold {signatures.get('threshold', math.nan):.2f} chi-square per "
                 f"region (textbook bound {signatures.get('theory', math.nan):.2f})"
                 if random else f"patterns matched up to {diagnosis.PATTERN_MATCH}")
    lines = [f"chapter {chapter}: {len(graded)} variants graded in {seconds:.0f} s "
             f"(two at a time; runs replayed from an earlier suite run: {replayed}, "
             f"run anew: {made}); the mistakes' signatures ready in {signing:.0f} s, "
             f"{threshold}; a diagnosis takes at most "
             f"{max(c['diagnosis seconds'] for _, _, c in graded.values()):.3f} s"]
    for variant, (results, elapsed, counts) in graded.items():
        total = sum(t["max_score"] for t in results["tests"])
        kind = "held-out" if variant.held_out else "correct" if variant.correct else "wrong"
        lines.append(f"{kind:8} {results['score'] / total:6.0%}  {elapsed:5.0f} s  "
                     f"{variant.name}  -> diagnosed as: "
                     f"{'; '.join(diagnosed(counts)) or 'nothing'}")
        lines += [f"            {t['score']:>4} / {t['max_score']:<4} {t['name']}"
                  for t in results["tests"]]
    (ARTIFACTS / f"grading-catalogue-{chapter[:2]}.txt").write_text("\n".join(lines) + "\n")
    # The same for the instructors page's tables (tools/course_tools/cli/measured_pages.py).
    variants = [{"name": variant.name, "correct": variant.correct,
                 "held_out": variant.held_out, "recognisable": variant.recognisable,
                 "score": results["score"] / sum(t["max_score"] for t in results["tests"]),
                 "diagnosed": diagnosed(counts), "as_meant": as_meant(variant, counts)}
                for variant, (results, _, counts) in graded.items() if variant.edits]
    (ARTIFACTS / f"grading-catalogue-{chapter[:2]}.json").write_text(
        json.dumps({"chapter": chapter, "variants": variants,
                    "confusable": signatures.get("confusable", [])}, indent=1) + "\n")


@pytest.mark.parametrize("variant", VARIANTS,
                         ids=[f"{v.chapter[:2]}-{'correct' if v.correct else 'wrong'}-{v.slug}"
                              for v in VARIANTS])
def test_catalogue_variant(variant, catalogue_results):
    """The solution itself: full marks. Correct but different: at least 90%. Plausibly
    wrong: at most half. The diagnosis (from seeds 1, 2, ..., which the signatures do
    not use): nothing for a correct variant; a wrong one named as itself or as a
    mistake declared to have the same effect, and as nothing else (a mistake the
    catalogue calls not recognisable, a data race, may be named as nothing); a held-out
    one as the mistake it makes."""
    results, _, counts = catalogue_results[variant]
    total = sum(t["max_score"] for t in results["tests"])
    scores = {t["name"]: (t["score"], t["output"].splitlines()[0]) for t in results["tests"]}
    names = diagnosed(counts)
    if not variant.edits:
        assert results["score"] == total, scores
    elif variant.correct:
        assert results["score"] >= 0.9 * total, scores
    else:
        assert results["score"] <= 0.5 * total, scores
    if variant.correct:
        assert names == [], names
        assert "extra_data" not in results or results["score"] < total
        return
    meant = variant.held_out or variant.name
    effects = {v.name: v.same_effect for v in grading_catalogue.CATALOGUE[variant.chapter[:2]]
               if v.same_effect}
    assert names or not variant.recognisable, \
        f"{variant.name}: diagnosed as nothing ({counts['diagnosis']})"
    assert all(diagnosis.related(name, meant, effects) for name in names), \
        f"{variant.name}: diagnosed as {names}"
    assert results["extra_data"]["diagnosis"]["matches"] == counts["diagnosis"]["matches"]
    assert ("look like" in results["output"]) == bool(names)


def test_starter_readme_says_what_the_grader_runs():
    """./course test runs the book's checks, not the grader's: the README says so."""
    from course_tools.editions import classroom
    text = classroom.STUDENT_README
    assert "the same checks your grader runs" not in text
    assert "not your grader's" in text and "statistics" in text
