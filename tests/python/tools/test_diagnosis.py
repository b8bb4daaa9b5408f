"""The diagnosis of a failing submission (tools/course_tools/grading/diagnosis.py) on
made-up measurements whose truth is known: a mistake is recognised from seeds its
signature was not made from, a correct picture and an uncatalogued mistake are named
as nothing, mistakes that cannot be told apart are named together, and stops and
deterministic patterns match as they should. The catalogues graded for real are
test_grading_statistics.py's."""

import math

import numpy as np
import pytest

from course_tools.grading import diagnosis
from course_tools.grading.grading_statistics import diagnosis_measurement

SIZE = 32
RUNS, SPP = 8, 64


def truth() -> np.ndarray:
    """A smooth made-up picture, brighter towards the top right, a different colour."""
    y, x = np.mgrid[0:SIZE, 0:SIZE] / SIZE
    return np.stack([0.2 + 0.5 * x, 0.3 + 0.4 * y, 0.1 + 0.2 * x * y], axis=-1)


def mistakes() -> dict[str, np.ndarray]:
    picture = truth()
    darker = picture * 0.9
    corner = picture.copy()
    corner[:8, :8] *= 1.5
    bluer = picture.copy()
    bluer[..., 2] *= 1.2
    top = picture.copy()
    top[:SIZE // 2] *= 1.08
    return {"ten per cent darker": darker, "a bright corner": corner,
            "too blue": bluer, "upper half brighter": top}


def renders(picture: np.ndarray, rng, runs: int = RUNS, spp: int = SPP,
            wobble: float = 0.0) -> np.ndarray:
    """`runs` noisy renders of `spp` samples (gamma noise, as the grading's own made-up
    pictures); with wobble, each whole run also scaled by 1 +- wobble (a mistake whose
    effect changes from run to run)."""
    shape = (runs,) + picture.shape
    samples = rng.gamma(spp * 4.0, 1.0 / (spp * 4.0), size=shape)  # mean 1, sd 0.5/sqrt(spp)
    scale = 1.0 + wobble * rng.uniform(-1.0, 1.0, size=(runs, 1, 1, 1))
    return picture * samples * scale


def measure(picture: np.ndarray, rng, runs: int = RUNS, spp: int = SPP,
            wobble: float = 0.0) -> dict:
    """A statistical test's measurement, as grading_statistics takes it."""
    return {"picture": diagnosis_measurement(renders(picture, rng, runs, spp, wobble))}


def signatures_of(pictures: dict[str, np.ndarray], rng, same_effect=None,
                  wobbles=None) -> dict:
    folds = {name: [measure(p, rng, wobble=(wobbles or {}).get(name, 0.0))
                    for _ in range(diagnosis.FOLDS)]
             for name, p in pictures.items()}
    calibration = diagnosis.calibrate(folds, same_effect or {},
                                      remeasure=diagnosis_measurement)
    return {"chapter": "11_path_tracing", "threshold": calibration["threshold"],
            "confusable": calibration["confusable"],
            "mistakes": [{"name": name, "explanation": f"{name}, explained",
                          "section": "Russian roulette", "anchor": "russian-roulette",
                          "threshold": calibration["thresholds"][name],
                          "tests": calibration["signatures"][name]} for name in pictures]}


def named(found) -> list[str]:
    return [m["name"] for m in found["matches"]]


def test_each_mistake_is_recognised_from_other_seeds():
    """Signatures from two sets of runs; each mistake measured again at twenty more
    sets is named, and named alone."""
    rng = np.random.default_rng(7)
    pictures = mistakes()
    signatures = signatures_of(pictures, rng)
    assert signatures["confusable"] == []
    for name, picture in pictures.items():
        for _ in range(20):
            assert named(diagnosis.diagnose(measure(picture, rng), signatures)) == [name]


def test_a_correct_picture_and_an_unknown_mistake_are_named_as_nothing():
    rng = np.random.default_rng(8)
    signatures = signatures_of(mistakes(), rng)
    for _ in range(20):
        assert named(diagnosis.diagnose(measure(truth(), rng), signatures)) == []
    unknown = truth()
    unknown[SIZE // 2:, :, 0] *= 0.7  # the lower half's red: not catalogued
    found = diagnosis.diagnose(measure(unknown, rng), signatures)
    assert found["matches"] == [] and found["nearest"]["distance"] > 1.0
    text = diagnosis.describe(found)
    assert text.startswith("None of this chapter's 4 catalogued mistakes")


def test_a_wrong_diagnosis_would_fail_this_test():
    """The test above can fail: a picture with the same bias as a catalogued mistake,
    but not that mistake's code, is named as it (the diagnosis sees pictures only)."""
    rng = np.random.default_rng(9)
    signatures = signatures_of(mistakes(), rng)
    lookalike = truth() * 0.9  # darker by another cause: the same expected picture
    assert named(diagnosis.diagnose(measure(lookalike, rng), signatures)) == \
        ["ten per cent darker"]


def test_mistakes_with_the_same_pictures_are_named_together():
    """Two mistakes whose expected pictures are alike: the calibration reports them
    confusable, and the diagnosis names both (never one of them with confidence)."""
    rng = np.random.default_rng(10)
    pictures = mistakes()
    pictures["ten per cent darker, another way"] = truth() * 0.9
    signatures = signatures_of(pictures, rng)
    assert ["ten per cent darker", "ten per cent darker, another way"] in \
        signatures["confusable"]
    found = diagnosis.diagnose(measure(truth() * 0.9, rng), signatures)
    assert sorted(named(found)) == ["ten per cent darker", "ten per cent darker, another way"]
    assert "cannot tell them apart" in diagnosis.describe(found)
    declared = signatures_of(pictures, rng, {"ten per cent darker, another way":
                                             "ten per cent darker"})
    assert declared["confusable"] == []


def test_the_threshold_comes_from_leave_seeds_out():
    """Without the runs to split, each fold is held out against the other: regions off
    by more than their noise says make the threshold rise above the textbook bound, to
    MARGIN times the largest held-out distance."""
    rng = np.random.default_rng(11)
    folds = {}
    for name, picture in mistakes().items():
        folds[name] = []
        for k in range(diagnosis.FOLDS):
            measured = measure(picture, rng)["picture"]
            means = np.array(measured["means"])
            means[:3] *= 1.02 if k else 0.98  # a few regions off by more than their noise
            folds[name].append({"picture": diagnosis.statistical_measurement(
                means, np.array(measured["variances"]), measured["noise"])})
    calibration = diagnosis.calibrate(folds, {})
    assert calibration["threshold"] > calibration["theory"]
    assert max(calibration["held_out"].values()) == pytest.approx(1.0 / diagnosis.MARGIN)


def test_a_mistake_whose_effect_changes_from_run_to_run_is_still_recognised():
    """A mistake that scales each whole run by up to 15% (as dropping a random part of
    a queue does) has a long tail of distances: split many ways, its own runs give it a
    threshold of its own, wide enough that new runs of it are recognised (nearly
    always: a miss says "nothing matches", never another name), while the steady
    mistakes keep theirs narrow; with the textbook bound, it would be missed."""
    rng = np.random.default_rng(15)
    pictures = mistakes()
    pictures["wobbling"] = truth() * 1.3
    signatures = signatures_of(pictures, rng, wobbles={"wobbling": 0.15})
    thresholds = {m["name"]: m["threshold"] for m in signatures["mistakes"]}
    assert thresholds["wobbling"] > 2 * diagnosis.chi_square_bound(192)
    assert max(t for name, t in thresholds.items() if name != "wobbling") < \
        2 * diagnosis.chi_square_bound(192)
    recognised = [named(diagnosis.diagnose(measure(pictures["wobbling"], rng, wobble=0.15),
                                           signatures)) for _ in range(40)]
    assert recognised.count(["wobbling"]) >= 36 and \
        recognised.count([]) == 40 - recognised.count(["wobbling"])
    narrow = {**signatures, "mistakes": [{**m, "threshold": diagnosis.chi_square_bound(192)}
                                         for m in signatures["mistakes"]]}
    missed = [named(diagnosis.diagnose(measure(pictures["wobbling"], rng, wobble=0.15),
                                       narrow)) for _ in range(40)]
    assert missed.count([]) >= 8


def test_a_restarting_generator_is_told_from_the_right_picture_by_its_noise():
    """The solution's expectation with a single sample's noise (every pass starting
    again from the seed): chi-square alone would match it to anything; the noise tells
    it apart, both ways round."""
    rng = np.random.default_rng(16)
    pictures = mistakes()
    folds = {name: [measure(p, rng) for _ in range(diagnosis.FOLDS)]
             for name, p in pictures.items()}
    folds["restarting"] = [measure(truth(), rng, spp=1) for _ in range(diagnosis.FOLDS)]
    calibration = diagnosis.calibrate(folds, {}, remeasure=diagnosis_measurement)
    signatures = {"chapter": "A1_fragment_passes", "threshold": calibration["threshold"],
                  "mistakes": [{"name": name, "explanation": "", "section": "", "anchor": "",
                                "threshold": calibration["thresholds"][name], "tests": tests}
                               for name, tests in calibration["signatures"].items()]}
    assert named(diagnosis.diagnose(measure(truth(), rng, spp=1), signatures)) == \
        ["restarting"]
    assert named(diagnosis.diagnose(measure(truth(), rng), signatures)) == []
    assert named(diagnosis.diagnose(measure(truth() * 0.9, rng, spp=1), signatures)) == []


def test_chi_square_bound_agrees_with_sampling():
    rng = np.random.default_rng(12)
    for count in (48, 192):
        sampled = np.quantile(rng.chisquare(count, size=2_000_000), 1 - diagnosis.MATCH_ALPHA)
        assert diagnosis.chi_square_bound(count) == pytest.approx(sampled / count, rel=0.01)


def test_stops_and_patterns():
    """A NaN picture matches the mistakes that make NaNs, and only on that test; a
    program that failed to run is named as nothing; deterministic pictures match by
    their difference pattern, up to PATTERN_MATCH."""
    rng = np.random.default_rng(13)
    reference = rng.uniform(0, 255, size=(64, 64, 3))
    shadowless = reference.copy()
    shadowless[40:, :] += 60.0
    flipped = reference[::-1]
    image = {"shadowless": diagnosis.image_measurement(shadowless, reference),
             "flipped": diagnosis.image_measurement(flipped, reference)}
    signatures = {"chapter": "05_shading_shadows", "threshold": 1.0, "mistakes": [
        {"name": name, "explanation": "", "section": "", "anchor": "",
         "tests": {"lit": image[name], "nan": diagnosis.stopped("statistical", "nan")
                   if name == "flipped" else diagnosis.statistical_measurement(
                       np.ones(3), np.ones(3), 1.0)}} for name in image]}
    lighter = shadowless.copy()
    lighter[40:, :] += 3.0  # within rounding of the same mistake
    assert named(diagnosis.diagnose({"lit": diagnosis.image_measurement(lighter, reference)},
                                    signatures)) == ["shadowless"]
    half = reference.copy()
    half[52:, :] += 60.0  # half the shadowed rows: another mistake
    assert named(diagnosis.diagnose({"lit": diagnosis.image_measurement(half, reference)},
                                    signatures)) == []
    assert named(diagnosis.diagnose({"nan": diagnosis.stopped("statistical", "nan")},
                                    signatures)) == ["flipped"]
    # NaN pixels in one set of runs and not in another: that test tells nothing, the
    # picture that was compared decides.
    assert named(diagnosis.diagnose({"lit": diagnosis.image_measurement(lighter, reference),
                                     "nan": diagnosis.stopped("statistical", "nan")},
                                    signatures)) == ["shadowless"]
    failed = {"lit": diagnosis.stopped("image", "failed"),
              "nan": diagnosis.stopped("statistical", "failed")}
    assert diagnosis.diagnose(failed, signatures) is None
    assert diagnosis.diagnose({}, signatures) is None
    assert diagnosis.diagnose({"lit": image["flipped"]}, None) is None


def test_the_text_names_the_section_and_its_link(monkeypatch):
    rng = np.random.default_rng(14)
    signatures = signatures_of(mistakes(), rng)
    found = diagnosis.diagnose(measure(mistakes()["a bright corner"], rng), signatures)
    text = diagnosis.describe(found)
    assert "- a bright corner. a bright corner, explained" in text
    assert '"Russian roulette" (chapters/11_path_tracing/#russian-roulette)' in text
    monkeypatch.setenv("COURSE_BOOK_URL", "https://example.edu/raytracing/")
    assert diagnosis.book_link("11_path_tracing", "russian-roulette") == \
        "https://example.edu/raytracing/chapters/11_path_tracing/#russian-roulette"
    assert math.isfinite(found["matches"][0]["distance"])


def test_pictures_the_solution_could_draw_name_no_mistake():
    """A correct estimator a little noisier is, by chi-square, as close to a mistake that
    biases the picture by 1% as to the solution: with the solution's own signature
    beside the mistakes', no mistake is named; without it, the slight bias would be."""
    rng = np.random.default_rng(17)
    pictures = {"one per cent darker": truth() * 0.99}
    folds = {name: [measure(p, rng, spp=16) for _ in range(diagnosis.FOLDS)]
             for name, p in pictures.items()}
    calibration = diagnosis.calibrate(
        folds, {}, remeasure=diagnosis_measurement,
        solution=[measure(truth(), rng, spp=16) for _ in range(diagnosis.FOLDS)])
    entry = {"name": "one per cent darker", "explanation": "", "section": "", "anchor": "",
             "threshold": calibration["thresholds"]["one per cent darker"],
             "noise_tolerance": calibration["noise_tolerances"]["one per cent darker"],
             "tests": calibration["signatures"]["one per cent darker"]}
    right = {"tests": calibration["signatures"][diagnosis.SOLUTION],
             "threshold": calibration["thresholds"][diagnosis.SOLUTION],
             "noise_tolerance": calibration["noise_tolerances"][diagnosis.SOLUTION]}
    alone = {"chapter": "25_grid_media", "threshold": 1.0, "mistakes": [entry]}
    noisy = measure(truth(), rng, spp=12)
    assert named(diagnosis.diagnose(noisy, alone)) == ["one per cent darker"]
    found = diagnosis.diagnose(noisy, {**alone, "solution": right})
    assert named(found) == [] and found["like_solution"]
    assert "as close to the solution's" in diagnosis.describe(found)
    darker = measure(truth() * 0.9, rng, spp=16)  # far from both
    assert not diagnosis.diagnose(darker, {**alone, "solution": right})["like_solution"]
