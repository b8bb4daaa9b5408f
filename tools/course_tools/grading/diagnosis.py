"""Feedback that names the mistake: which catalogued wrong implementation a failing
submission's pictures look like (grading_catalogue: each chapter's plausible bugs).

1. A measurement per test, taken while grading (grading_statistics.py and grader.py):
   - a random picture ('statistical'): the region means of the finest blocks, each
     channel, with the variance of each mean (the grader's own estimate), and the
     picture's noise (the median pixel's variance between runs: a generator that
     restarts every pass has the solution's expectation but a single sample's noise);
   - a deterministic picture ('image'): where it differs from the solution's, with
     its sign: the mean signed difference of each 8 x 8 block and channel;
   - chapter 13's tree ('traversal'): per 8 x 8 block, the share of pixels whose
     nearest hit is not the solution's and the mean difference in work;
   - or how the test stopped before any comparison ('nan', 'negative', 'failed').
2. A signature per catalogued mistake: the grader grades the mistake like a student's
   submission at seeds no submission uses, in FOLDS sets of runs, and keeps the mean of
   each measurement (and, for random pictures, its variance). Made with the references
   (grader.prepare_signatures) and thrown away when they are.
3. A distance per test in units of the threshold at which a match is accepted (<= 1:
   the submission's pictures are what the mistake makes), the largest over the tests:
   - random pictures: chi-square per region of the submission's means against the
     mistake's, with both variances, and the log of the ratio of the two noises;
     each mistake's chi-square threshold is the larger of the chi-square quantile
     (MATCH_ALPHA, Wilson-Hilferty) and MARGIN x the largest distance met when its own
     runs, split SPLITS ways into a submission's worth held out and a signature made of
     the rest, were matched, and its noise tolerance likewise the larger of NOISE_MATCH
     and MARGIN x the largest log-ratio met (leave-seeds-out: the mistake
     recognised from seeds it was not learned from; many splits and a threshold of its
     own, because a mistake whose effect varies from run to run, as a queue that drops
     a random part of its work, has a long tail of distances that a steady one has not);
   - deterministic pictures: the relative difference of the two difference patterns,
     accepted up to PATTERN_MATCH;
   - a stop before comparison (NaN or negative pixels) matches the same stop and tells
     nothing against a picture that was compared (such pixels may come in one set of
     runs and not in another); a program that failed to run matches nothing (a crash
     has too many causes).
4. The diagnosis: the mistakes within the threshold, nearest first. Mistakes that the
   calibration found within each other's threshold (neither recognisable from the
   other) are named together; where none is within it, the diagnosis says so and
   names none. The solution has a signature too: pictures within its threshold (a
   correct but noisier estimator looks like a slightly biased one) name no mistake.
   Correct submissions are not diagnosed (grader.grade asks only when a test failed).
"""

from __future__ import annotations

import math
import os
from statistics import NormalDist

import numpy as np

from course_tools.grading.blocks import block_means

FOLDS = 2                       # sets of runs a random picture's signature is made of
FOLD_SEEDS = (3_000_001, 4_000_001)  # their first seeds: far from any other runs'
MATCH_ALPHA = 1e-3              # a true match's chance of exceeding the chi-square bound
MARGIN = 1.5                    # above the largest distance leave-seeds-out met
PATTERN_MATCH = 0.25            # deterministic patterns: relative difference accepted
PATTERN_BLOCKS = 8              # the deterministic patterns' blocks per side
NOISE_MATCH = math.log(2.0)     # noises within a factor of 2 of each other match
SPLITS = 32                     # held-out splits of each mistake's runs (calibration)
SOLUTION = "the solution"       # the solution's own signature, beside the mistakes
FLOOR_RELATIVE = 1e-4           # float rounding, as grading_statistics' floor
FLOOR_ABSOLUTE = 1e-5
STOPS = ("nan", "negative", "failed")


# ---------------------------------------------------------------- measurements

def statistical_measurement(means: np.ndarray, variances: np.ndarray, noise: float,
                            runs: np.ndarray | None = None) -> dict:
    """runs (the pictures themselves) stay in memory for the calibration's splits and
    are never written out."""
    measured = {"kind": "statistical", "status": "compared",
                "means": [float(x) for x in means.ravel()],
                "variances": [float(x) for x in variances.ravel()], "noise": float(noise)}
    if runs is not None:
        measured["runs"] = runs
    return measured


def image_measurement(image: np.ndarray, reference: np.ndarray) -> dict:
    """8-bit pictures (H, W, 3): the signed block means of the difference, in 1/255."""
    return {"kind": "image", "status": "compared",
            "pattern": [float(x) for x in
                        block_means(image - reference, PATTERN_BLOCKS).ravel()]}


def traversal_measurement(hits_differ: np.ndarray, work_difference: np.ndarray) -> dict:
    """Chapter 13's views: per block, the share of pixels whose nearest hit differs from
    the solution's, and the mean difference in work (in heat-map scales)."""
    return {"kind": "traversal", "status": "compared",
            "pattern": [float(x) for x in np.concatenate(
                [block_means(hits_differ.astype(np.float64), PATTERN_BLOCKS).ravel(),
                 block_means(work_difference, PATTERN_BLOCKS).ravel()])]}


def stopped(kind: str, why: str) -> dict:
    assert why in STOPS, why
    return {"kind": kind, "status": why}


# ---------------------------------------------------------------- signatures

def signature(folds: list[dict]) -> dict:
    """One test's signature from its measurement in each fold: the same stop in every
    fold, or the mean pattern, or the mean of the region means with the variance of
    that mean. Folds that disagree on how the test ends make it 'unstable': it tells
    nothing about the mistake and is not compared."""
    statuses = {m["status"] for m in folds}
    if len(statuses) != 1:
        return {"kind": folds[0]["kind"], "status": "unstable"}
    first = folds[0]
    if first["status"] != "compared":
        return dict(first)
    if first["kind"] == "statistical":
        means = np.mean([m["means"] for m in folds], axis=0)
        variances = np.mean([m["variances"] for m in folds], axis=0) / len(folds)
        noise = float(np.exp(np.mean([np.log(max(m["noise"], 1e-300)) for m in folds])))
        return statistical_measurement(means, variances, noise)
    return {**first, "pattern": [float(x) for x in
                                 np.mean([m["pattern"] for m in folds], axis=0)]}


def chi_square_bound(count: int, alpha: float = MATCH_ALPHA) -> float:
    """The chi-square quantile per degree of freedom exceeded with chance alpha
    (Wilson-Hilferty's cube-root normal approximation: no scipy in the grading layer)."""
    z = NormalDist().inv_cdf(1.0 - alpha)
    k = 2.0 / (9.0 * count)
    return (1.0 - k + z * math.sqrt(k)) ** 3


def chi_square_per_region(measured: dict, expected: dict) -> float:
    mine, theirs = np.array(measured["means"]), np.array(expected["means"])
    if mine.shape != theirs.shape:
        return math.inf
    floor = FLOOR_RELATIVE * np.abs(theirs) + FLOOR_ABSOLUTE
    variance = np.array(measured["variances"]) + np.array(expected["variances"]) + floor ** 2
    return float(np.mean((mine - theirs) ** 2 / variance))


def noise_difference(measured: dict, expected: dict) -> float:
    """|log| of the ratio of two noises; 0 when both pictures have none."""
    tiny = 1e-12 * max(measured["noise"], expected["noise"], 1e-30)
    return abs(math.log((measured["noise"] + tiny) / (expected["noise"] + tiny)))


def pattern_difference(measured: dict, expected: dict) -> float:
    mine, theirs = np.array(measured["pattern"]), np.array(expected["pattern"])
    if mine.shape != theirs.shape:
        return math.inf
    return float(np.linalg.norm(mine - theirs) / max(np.linalg.norm(theirs), 1e-6))


def test_distance(measured: dict | None, expected: dict, threshold: float,
                  noise_tolerance: float = NOISE_MATCH) -> float | None:
    """One test's distance in threshold units (<= 1 matches), or None when it tells
    nothing (not measured, or the mistake's own runs disagree)."""
    if measured is None or expected["status"] == "unstable":
        return None
    if measured["status"] == expected["status"] == "failed":
        return None  # a crash or a missing output has too many causes to name one
    if measured["status"] != expected["status"]:
        if {measured["status"], expected["status"]} & {"nan", "negative"}:
            # A NaN or a negative pixel may come in one set of runs and not in the next
            # (chapter 16's total internal reflection without its case, on Mesa 25):
            # the test tells nothing, the others decide.
            return None
        return math.inf
    if measured["status"] != "compared":
        return 0.0
    if measured["kind"] == "statistical":
        return max(chi_square_per_region(measured, expected) / threshold,
                   noise_difference(measured, expected) / noise_tolerance)
    return pattern_difference(measured, expected) / PATTERN_MATCH


def distance(measured: dict[str, dict], tests: dict[str, dict], threshold: float,
             noise_tolerance: float = NOISE_MATCH) -> float:
    """A submission's distance from a mistake: the largest over the tests both have
    (inf when no test tells anything)."""
    found = [test_distance(measured.get(slug), expected, threshold, noise_tolerance)
             for slug, expected in tests.items()]
    found = [d for d in found if d is not None]
    return max(found) if found else math.inf


def calibrate(folds_by_mistake: dict[str, list[dict[str, dict]]],
              same_effect: dict[str, str], remeasure=None, seed: int = 1,
              solution: list[dict[str, dict]] | None = None) -> dict:
    """Each mistake's tolerances (chi-square per region and noise) for random pictures,
    and the pairs of mistakes they cannot tell apart. folds_by_mistake: mistake -> one
    measurement dictionary (test slug -> measurement) per fold; solution: the solution's
    own folds, calibrated the same way (a submission that matches the solution as well
    as a mistake is not diagnosed). remeasure(runs) measures a random picture's runs as
    the grader does: with it, each mistake's runs (all folds together) are split SPLITS
    times into a submission's worth and the rest; without it (or without the runs), each
    fold is held out against the others."""
    everyone = dict(folds_by_mistake)
    if solution:
        everyone[SOLUTION] = solution
    counts = [len(m["means"]) for folds in everyone.values() for fold in folds
              for m in fold.values() if m["kind"] == "statistical"
              and m["status"] == "compared"]
    theory = chi_square_bound(min(counts)) if counts else 1.0
    rng = np.random.default_rng(seed)
    held_out: dict[str, list[float]] = {}
    noise_held_out: dict[str, list[float]] = {}
    for name, folds in everyone.items():
        held_out[name], noise_held_out[name] = [], []
        for mine, learned in held_out_pairs(folds, remeasure, rng):
            for slug, expected in learned.items():
                measured = mine.get(slug)
                if measured is None or measured["status"] != "compared" or \
                        expected["status"] != "compared" or measured["kind"] != "statistical":
                    continue
                held_out[name].append(chi_square_per_region(measured, expected))
                noise_held_out[name].append(noise_difference(measured, expected))
    finite = lambda values: [v for v in values if math.isfinite(v)]  # noqa: E731
    thresholds = {name: max(theory, MARGIN * max(finite(ds), default=0.0))
                  for name, ds in held_out.items()}
    noise_tolerances = {name: max(NOISE_MATCH, MARGIN * max(finite(ds), default=0.0))
                        for name, ds in noise_held_out.items()}
    signatures = {name: {slug: signature([f[slug] for f in folds])
                         for slug in folds[0] if all(slug in f for f in folds)}
                  for name, folds in everyone.items()}
    confusable = set()
    for name, folds in everyone.items():
        for other, tests in signatures.items():
            if other == name or related(name, other, same_effect):
                continue
            if any(distance(fold, tests, thresholds[other], noise_tolerances[other]) <= 1.0
                   for fold in folds):
                confusable.add(tuple(sorted((name, other))))
    return {"threshold": max(thresholds.values(), default=theory), "theory": theory,
            "thresholds": thresholds, "noise_tolerances": noise_tolerances,
            "held_out": {name: max(ds, default=0.0) / thresholds[name]
                         for name, ds in held_out.items()},
            "noise_held_out": {name: max(ds, default=0.0) / noise_tolerances[name]
                               for name, ds in noise_held_out.items()},
            "confusable": [list(pair) for pair in sorted(confusable)],
            "signatures": signatures}


def held_out_pairs(folds: list[dict[str, dict]], remeasure, rng):
    """(a submission's worth of measurements, a signature made without them), for one
    mistake: SPLITS random splits of its runs when they were kept and can be measured
    again, else each fold against the others."""
    slugs = [slug for slug in folds[0] if all(slug in f for f in folds)]
    splittable = [s for s in slugs if all("runs" in f[s] for f in folds)]
    if remeasure is None or not splittable or len(folds) < 2:
        for k, fold in enumerate(folds):
            others = [f for j, f in enumerate(folds) if j != k] or [fold]
            yield fold, {slug: signature([f[slug] for f in others]) for slug in slugs}
        return
    pooled = {s: np.concatenate([f[s]["runs"] for f in folds]) for s in splittable}
    for _ in range(SPLITS):
        mine, learned = {}, {}
        for slug, runs in pooled.items():
            size = len(folds[0][slug]["runs"])  # a submission's runs
            order = rng.permutation(len(runs))
            mine[slug] = remeasure(runs[order[:size]])
            learned[slug] = signature([remeasure(runs[order[size:]])])
        yield mine, learned


def related(one: str, other: str, same_effect: dict[str, str]) -> bool:
    """Declared to have the same effect (either way round, or through a third)."""
    def root(name):
        seen = set()
        while name in same_effect and name not in seen:
            seen.add(name)
            name = same_effect[name]
        return name
    return root(one) == root(other)


# ---------------------------------------------------------------- diagnosis

def book_link(chapter: str, anchor: str) -> str:
    """Where the book teaches it: the page's address under COURSE_BOOK_URL when the
    instructor publishes the book there, else its path in the book's site."""
    base = os.environ.get("COURSE_BOOK_URL", "").rstrip("/")
    page = f"chapters/{chapter}/" + (f"#{anchor}" if anchor else "")
    return f"{base}/{page}" if base else page


def diagnose(measured: dict[str, dict], signatures: dict) -> dict | None:
    """The catalogued mistakes a submission's measurements match (signatures: what
    prepare_signatures wrote). None when there is nothing to compare (no signatures,
    or no test measured)."""
    if not signatures or not measured:
        return None
    def away(entry: dict) -> float:
        return distance(measured, entry["tests"], entry.get("threshold", signatures["threshold"]),
                        entry.get("noise_tolerance", NOISE_MATCH))

    scored = sorted(((away(m), m) for m in signatures["mistakes"]), key=lambda pair: pair[0])
    if not scored or all(v["status"] == "failed" for v in measured.values()):
        return None
    # Pictures that the solution's own runs could have drawn as well: no mistake is named
    # with confidence (the grader's test, which failed, is the sharper one).
    like_solution = signatures.get("solution") is not None and \
        away(signatures["solution"]) <= 1.0
    matches = [] if like_solution else [
        {"name": m["name"], "distance": round(d, 3), "explanation": m["explanation"],
         "section": m["section"], "link": book_link(signatures["chapter"], m["anchor"])}
        for d, m in scored if d <= 1.0]
    nearest = scored[0]
    return {"matches": matches, "catalogued": len(signatures["mistakes"]),
            "like_solution": like_solution,
            "nearest": {"name": nearest[1]["name"],
                        "distance": round(nearest[0], 3) if math.isfinite(nearest[0])
                        else None}}


def describe(diagnosis: dict | None) -> str:
    """The diagnosis in a few lines for the report and results.json."""
    if diagnosis is None:
        return ""
    matches = diagnosis["matches"]
    if not matches:
        nearest = diagnosis["nearest"]
        far = (f" (the nearest, \"{nearest['name']}\", is {nearest['distance']:.1f} times "
               "as far as a match may be)") if nearest["distance"] is not None else ""
        if diagnosis.get("like_solution"):
            return ("No catalogued mistake is named: by the diagnosis's measures these "
                    "pictures are as close to the solution's as to any mistake's.")
        return (f"None of this chapter's {diagnosis['catalogued']} catalogued mistakes "
                f"matches these pictures{far}: the measurements are what the grader saw.")
    lines = ["These pictures look like " + (
        "a known mistake:" if len(matches) == 1 else
        "one of these known mistakes (the measurements cannot tell them apart):")]
    for match in matches:
        lines.append(f"- {match['name']}. {match['explanation']}")
        lines.append(f"  The book explains it in \"{match['section']}\" ({match['link']}). "
                     f"Match: {match['distance']:.2f} of the threshold (1 and below "
                     "match; calibrated on the mistake's own runs at other seeds).")
    return "\n".join(lines)
