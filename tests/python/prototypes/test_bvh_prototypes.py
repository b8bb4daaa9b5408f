"""Chapter 13's Python side: the 2D binned-SAH prototype (python_prototypes/bvh_2d.py)
and the benchmark plot (python_prototypes/bench_plot.py)."""

import json

import numpy as np
import pytest

from conftest import ROOT  # noqa: F401  (puts python_prototypes on sys.path)

from python_prototypes import bench_plot
from python_prototypes import bvh_2d


# ---------------------------------------------------------------------------------------
# bvh_2d: the SAH on a case small enough to work out by hand
# ---------------------------------------------------------------------------------------

def unit_triangles(xs):
    """Right triangles (x, 0), (x + 1, 0), (x, 1): boxes [x, x + 1] x [0, 1]."""
    return np.array([[[x, 0.0], [x + 1.0, 0.0], [x, 1.0]] for x in xs])


# Two pairs, far apart: boxes [0,1], [1,2] and [10,11], [11,12] (all 1 high).
PAIRS = unit_triangles([0.0, 1.0, 10.0, 11.0])


def test_sah_costs_of_two_pairs_by_hand():
    lower, upper = bvh_2d.triangle_boxes(PAIRS)
    candidates = bvh_2d.sah_candidates(lower, upper, axis=0, bins=16)
    # Centroids at x = 0.5, 1.5, 10.5, 11.5: bins 0, 1, 14 and 15 of 16 over 11 units.
    assert candidates.bin_of.tolist() == [0, 1, 14, 15]
    # The root's half-perimeter is 12 + 1 = 13. Plane 0 puts [0,1] (2) alone on the left
    # and [1,12] (12) with three on the right: 1 + (2 * 1 + 12 * 3) / 13.
    assert candidates.costs[0] == pytest.approx(1.0 + 38.0 / 13.0)
    # Planes 1 ... 13 separate the pairs, each pair's box [0,2] or [10,12] (3):
    # 1 + (3 * 2 + 3 * 2) / 13, the same for all of them: the first one wins.
    assert np.allclose(candidates.costs[1:14], 1.0 + 12.0 / 13.0)
    assert candidates.costs[14] == pytest.approx(1.0 + 38.0 / 13.0)
    assert candidates.left_counts.tolist() == [1] + [2] * 13 + [3]
    # Along y every centroid is at 1/3: no candidates.
    assert bvh_2d.sah_candidates(lower, upper, axis=1) is None
    axis, plane, cost, _ = bvh_2d.best_split(lower, upper)
    assert (axis, plane) == (0, 1)
    assert cost == pytest.approx(1.0 + 12.0 / 13.0)


def test_two_pairs_make_a_root_and_two_leaves():
    root = bvh_2d.build(PAIRS, max_leaf=4)
    # Splitting a pair would cost 1 + (2 + 2) / 3 = 2.33 > 2, testing both triangles.
    assert [sorted(child.triangles.tolist()) for child in root.children] == [[0, 1], [2, 3]]
    assert all(child.is_leaf for child in root.children)
    assert root.split[0] == 0 and 1.5 < root.split[1] < 10.5
    # A line through the root box: the root, then each pair with chance 3/13.
    assert bvh_2d.sah_cost(root) == pytest.approx(1.0 + 12.0 / 13.0)


def test_one_triangle_and_identical_triangles():
    one = bvh_2d.build(unit_triangles([3.0]))
    assert one.is_leaf and one.triangles.tolist() == [0]
    # Nine copies: no plane separates them, so the list is halved until it fits in a
    # leaf: 9 -> 4 + 5, 5 -> 2 + 3.
    same = bvh_2d.build(unit_triangles([2.0] * 9), max_leaf=4)
    leaves = [node for node in bvh_2d.nodes_of(same) if node.is_leaf]
    assert [len(leaf.triangles) for leaf in leaves] == [4, 2, 3]


@pytest.mark.parametrize("max_leaf", [1, 2, 4])
def test_random_trees_keep_the_invariants(max_leaf):
    triangles = bvh_2d.random_triangles(150, seed=7)
    lower, upper = bvh_2d.triangle_boxes(triangles)
    root = bvh_2d.build(triangles, max_leaf=max_leaf)
    seen = []
    for node in bvh_2d.nodes_of(root):
        # Tight boxes: exactly around the triangles below.
        assert np.allclose(node.lower, lower[node.triangles].min(axis=0))
        assert np.allclose(node.upper, upper[node.triangles].max(axis=0))
        if node.is_leaf:
            assert 1 <= len(node.triangles) <= max_leaf
            seen.extend(node.triangles.tolist())
        else:
            assert len(node.children) == 2
            for child in node.children:  # children inside their parent
                assert np.all(child.lower >= node.lower) and np.all(child.upper <= node.upper)
                assert child.depth == node.depth + 1
    assert sorted(seen) == list(range(150))  # every triangle in exactly one leaf
    # Far cheaper than testing all 150 triangles, and deterministic.
    assert bvh_2d.sah_cost(root) < 0.2 * 150
    again = bvh_2d.build(bvh_2d.random_triangles(150, seed=7), max_leaf=max_leaf)
    assert [n.triangles.tolist() for n in bvh_2d.nodes_of(again)] == \
        [n.triangles.tolist() for n in bvh_2d.nodes_of(root)]


def test_bvh_2d_writes_its_figure(tmp_path):
    figure = tmp_path / "bvh_2d.png"
    assert bvh_2d.main(["--triangles", "40", "--figure", str(figure)]) == 0
    assert figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


# ---------------------------------------------------------------------------------------
# bench_plot
# ---------------------------------------------------------------------------------------

# Made-up numbers, only to exercise the plot: not measurements.
EXAMPLE = {
    "title": "example, not a measurement",
    "results": [
        {"triangles": 500, "rays": "primary", "method": "brute_force", "rays_per_second": 2e6},
        {"triangles": 500, "rays": "primary", "method": "bvh", "rays_per_second": 2e7},
        {"triangles": 5000, "rays": "primary", "method": "brute_force", "rays_per_second": 2e5},
        {"triangles": 5000, "rays": "primary", "method": "bvh", "rays_per_second": 1.5e7},
        {"triangles": 5000, "rays": "diffuse", "method": "brute_force", "rays_per_second": 1e5},
        {"triangles": 5000, "rays": "diffuse", "method": "bvh", "rays_per_second": 4e6},
        {"triangles": 500000, "rays": "primary", "method": "bvh", "rays_per_second": 1e7},
        {"triangles": 500000, "rays": "primary", "method": "bvh", "rays_per_second": 1.2e7},
    ],
}


def test_bench_plot_reads_and_plots(tmp_path):
    source = tmp_path / "bench.json"
    source.write_text(json.dumps(EXAMPLE))
    title, records = bench_plot.load_results(source)
    assert title == "example, not a measurement"
    # Repeated measurements are averaged; missing combinations are just missing.
    assert bench_plot.series(records, "primary", "bvh") == \
        [(500, 2e7), (5000, 1.5e7), (500000, 1.1e7)]
    assert bench_plot.series(records, "diffuse", "bvh") == [(5000, 4e6)]
    assert bench_plot.speedups(records, "primary") == [(500, 10.0), (5000, 75.0)]
    assert bench_plot.speedups(records, "diffuse") == [(5000, 40.0)]
    figure = tmp_path / "scaling.png"
    assert bench_plot.main(["--input", str(source), "--figure", str(figure)]) == 0
    assert figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # A plain list works too, and without brute force there is one panel.
    plain = tmp_path / "plain.json"
    plain.write_text(json.dumps([r for r in EXAMPLE["results"] if r["method"] == "bvh"]))
    assert bench_plot.main(["--input", str(plain), "--figure", str(tmp_path / "p.png")]) == 0


@pytest.mark.parametrize("content, message", [
    ("not json", "Expecting value"),
    ("[]", "non-empty list"),
    ('[{"triangles": 5}]', "missing method, rays, rays_per_second"),
    ('[{"triangles": 5, "rays": "shadow", "method": "bvh", "rays_per_second": 1}]',
     "rays must be one of primary, diffuse"),
    ('[{"triangles": 5, "rays": "primary", "method": "grid", "rays_per_second": 1}]',
     "method must be one of brute_force, bvh"),
    ('[{"triangles": 0, "rays": "primary", "method": "bvh", "rays_per_second": 1}]',
     "triangles must be a positive number"),
    ('{"results": [{"triangles": 5, "rays": "primary", "method": "bvh", '
     '"rays_per_second": -1}]}', "result 0: rays_per_second must be a positive number"),
])
def test_bench_plot_refuses_bad_input(tmp_path, capsys, content, message):
    source = tmp_path / "bad.json"
    source.write_text(content)
    assert bench_plot.main(["--input", str(source), "--figure", str(tmp_path / "x.png")]) == 3
    error = capsys.readouterr().err
    assert message in error and str(source) in error
    assert not (tmp_path / "x.png").exists()
