"""The surface area heuristic in its two forms: the expected cost of a ray through the
node (python_prototypes/bvh_2d.py, divided by the node's area A) and that cost times A
(chapters/14_bvh_sah/bvh.cpp, and the book's formula). Every candidate of a node, the leaf
included, carries the same factor A, so both forms must pick the same split and make
the same leaves; the book must print the code's form."""

import re

import numpy as np
import pytest

from conftest import ROOT

from python_prototypes import bvh_2d  # python_prototypes, on the path through conftest


def code_form_costs(lower, upper, axis, bins=bvh_2d.BINS, node_cost=bvh_2d.NODE_COST,
                    triangle_cost=bvh_2d.TRIANGLE_COST):
    """The candidates' costs as bvh.cpp computes them, written again: bin the centroids,
    sweep the bins' boxes from the right and from the left, and price each plane at
    node_cost * A + triangle_cost * (A_L n_L + A_R n_R), undivided. nan: one side empty."""
    centroids = 0.5 * (lower + upper)
    low, high = centroids[:, axis].min(), centroids[:, axis].max()
    if not high > low:
        return None
    bin_of = np.clip(((centroids[:, axis] - low) * (bins / (high - low))).astype(int),
                     0, bins - 1)
    box_lower = np.full((bins, 2), np.inf)
    box_upper = np.full((bins, 2), -np.inf)
    counts = np.zeros(bins, dtype=int)
    for index, b in enumerate(bin_of):
        box_lower[b] = np.minimum(box_lower[b], lower[index])
        box_upper[b] = np.maximum(box_upper[b], upper[index])
        counts[b] += 1

    def area(lo, hi):  # half the perimeter, bvh.cpp's halfArea() in 2D; 0 when empty
        return float(np.sum(hi - lo)) if np.all(hi >= lo) else 0.0

    node_area = area(lower.min(axis=0), upper.max(axis=0))
    right_areas = np.zeros(bins)
    lo, hi = np.full(2, np.inf), np.full(2, -np.inf)
    for b in range(bins - 1, 0, -1):
        lo, hi = np.minimum(lo, box_lower[b]), np.maximum(hi, box_upper[b])
        right_areas[b - 1] = area(lo, hi)
    costs = np.full(bins - 1, np.nan)
    lo, hi = np.full(2, np.inf), np.full(2, -np.inf)
    left_count = 0
    for b in range(bins - 1):
        lo, hi = np.minimum(lo, box_lower[b]), np.maximum(hi, box_upper[b])
        left_count += counts[b]
        right_count = len(lower) - left_count
        if left_count and right_count:
            costs[b] = node_cost * node_area + triangle_cost * (
                area(lo, hi) * left_count + right_areas[b] * right_count)
    return costs, node_area


def node_ranges(seed, count):
    """The triangle boxes of every node of the prototype's tree over a random scene."""
    triangles = bvh_2d.random_triangles(count, seed)
    lower, upper = bvh_2d.triangle_boxes(triangles)
    root = bvh_2d.build(triangles)
    return [(lower[n.triangles], upper[n.triangles]) for n in bvh_2d.nodes_of(root)
            if len(n.triangles) > 1]


@pytest.mark.parametrize("seed,count", [(1, 60), (2, 150), (3, 400), (7, 33)])
def test_both_forms_choose_the_same_split_and_the_same_leaves(seed, count):
    compared = 0
    for lower, upper in node_ranges(seed, count):
        book_best = bvh_2d.best_split(lower, upper)  # divided by the node's area
        code_best = None
        for axis in (0, 1):
            found = code_form_costs(lower, upper, axis)
            if found is None or np.all(np.isnan(found[0])):
                continue
            costs, node_area = found
            divided = bvh_2d.sah_candidates(lower, upper, axis).costs
            # The two forms differ by the node's area, the same for every candidate.
            assert np.allclose(costs, divided * node_area, equal_nan=True, rtol=1e-12)
            plane = int(np.nanargmin(costs))
            if code_best is None or costs[plane] < code_best[2]:
                code_best = (axis, plane, float(costs[plane]), node_area)
        if book_best is None:
            assert code_best is None
            continue
        assert (code_best[0], code_best[1]) == (book_best[0], book_best[1])
        # The leaf: n triangles cost triangle_cost * n, or that times A.
        n = len(lower)
        book_leaf = book_best[2] >= bvh_2d.TRIANGLE_COST * n
        code_leaf = code_best[2] >= bvh_2d.TRIANGLE_COST * n * code_best[3]
        assert book_leaf == code_leaf
        compared += 1
    assert compared > count // 8  # many nodes, not a trivial tree


def test_the_book_prints_the_codes_formula():
    page = (ROOT / "book" / "docs" / "chapters" / "14_bvh_sah.md").read_text()
    formulas = re.findall(r"\$\$(.*?)\$\$", page, flags=re.S)
    sah = [f for f in formulas if "C_{\\text{node}}" in f]
    assert len(sah) == 1, formulas
    assert "\\frac" not in sah[0] and "/ A" not in sah[0]
    assert re.search(r"C_\{\\text\{node\}\}\s*\\,\s*A\b", sah[0])
    assert re.search(r"A_L n_L \+ A_R n_R", sah[0])
    assert "C_{\\text{tri}} \\, n A" in page  # the leaf, times A too
    code = (ROOT / "chapters" / "14_bvh_sah" / "bvh.cpp").read_text()
    assert "options_.nodeCost * box.halfArea() +" in code
    assert "options_.triangleCost * (left.halfArea() * leftCount +" in code
    assert "leafCost = options_.triangleCost * count * box.halfArea();" in code
