"""A bounding volume hierarchy in 2D, built with the binned surface area heuristic.

The same algorithm as chapters/14_bvh_sah/bvh.cpp, in two dimensions so that it can be
drawn: boxes around small triangles, split again and again until a leaf holds a few.
In 2D the "surface area" of a box is its perimeter: a random line crosses a convex
shape with a probability proportional to its perimeter, as a random ray in 3D crosses a
convex body with a probability proportional to its surface area.

At each node, for each axis, the centroids' extent is cut into `bins` equal bins; the
bins - 1 planes between them are the candidate splits. A split's cost is

    cost = node_cost + triangle_cost * (P_left * n_left + P_right * n_right) / P_node

(P: half-perimeter, n: triangles): the price of visiting the node, plus the triangles
a line through the node tests, on average, in the children. The cheapest plane wins;
a range of at most `max_leaf` triangles becomes a leaf when testing all of its
triangles (triangle_cost * n) is no dearer.

    python python_prototypes/bvh_2d.py --figure bvh_2d.png
    python python_prototypes/bvh_2d.py --triangles 200 --seed 3 --figure more.png
"""

import argparse
import sys
from dataclasses import dataclass, field

import numpy as np

NODE_COST = 1.0      # visiting a node: one fetch, two box tests
TRIANGLE_COST = 1.0  # testing one triangle
BINS = 16
MAX_LEAF = 4


# ---------------------------------------------------------------------------------------
# Triangles and boxes
# ---------------------------------------------------------------------------------------

def random_triangles(count, seed=1):
    """`count` small triangles, (count, 3, 2), in the square [0, 10] x [0, 10]: three
    clusters of different size and a few scattered ones. Clusters are where the SAH
    earns its keep: a plane through the middle of the square would cut through them,
    a plane in the empty space between them costs far less."""
    random = np.random.default_rng(seed)
    centres = np.array([[2.5, 7.5], [7.5, 6.8], [4.8, 2.0]])
    spreads = np.array([0.8, 0.9, 0.5])
    shares = np.array([0.4, 0.3, 0.2])  # the rest is scattered everywhere
    which = random.choice(len(centres) + 1, size=count, p=[*shares, 1.0 - shares.sum()])
    clustered = which < len(centres)
    which = np.minimum(which, len(centres) - 1)
    middle = np.where(clustered[:, None],
                      centres[which] + random.normal(size=(count, 2)) * spreads[which, None],
                      random.uniform(0.5, 9.5, size=(count, 2)))
    middle = np.clip(middle, 0.3, 9.7)
    return middle[:, None, :] + random.uniform(-0.3, 0.3, size=(count, 3, 2))


def triangle_boxes(triangles):
    """Lower and upper corners of each triangle's box: two (n, 2) arrays."""
    triangles = np.asarray(triangles, dtype=np.float64)
    return triangles.min(axis=1), triangles.max(axis=1)


def half_perimeter(lower, upper):
    """Width + height of the box [lower, upper]; 0 for an empty box."""
    size = np.asarray(upper) - np.asarray(lower)
    if np.any(size < 0):
        return 0.0
    return float(size[0] + size[1])


def union(lower, upper):
    """The box around boxes (lower[i], upper[i])."""
    return lower.min(axis=0), upper.max(axis=0)


# ---------------------------------------------------------------------------------------
# The surface area heuristic
# ---------------------------------------------------------------------------------------

@dataclass
class Candidates:
    """The candidate planes along one axis of one node, and what each would cost."""
    axis: int
    positions: np.ndarray  # where each plane is, in world coordinates
    costs: np.ndarray      # the SAH cost of splitting there; nan: one side empty
    left_counts: np.ndarray
    bin_of: np.ndarray     # each triangle's bin: plane k sends bins 0 ... k left


def sah_candidates(lower, upper, axis, bins=BINS, node_cost=NODE_COST,
                   triangle_cost=TRIANGLE_COST):
    """The bins - 1 binned-SAH candidates along `axis` for triangles with boxes
    (lower, upper); None when all centroids have the same coordinate on that axis."""
    centroids = 0.5 * (lower + upper)
    low, high = centroids[:, axis].min(), centroids[:, axis].max()
    extent = high - low
    if not extent > 0.0:
        return None
    bin_of = np.clip(((centroids[:, axis] - low) * (bins / extent)).astype(int), 0, bins - 1)
    parent = half_perimeter(*union(lower, upper))
    costs = np.full(bins - 1, np.nan)
    left_counts = np.zeros(bins - 1, dtype=int)
    for plane in range(bins - 1):
        left = bin_of <= plane
        n_left, n_right = int(left.sum()), int((~left).sum())
        left_counts[plane] = n_left
        if n_left == 0 or n_right == 0:
            continue  # not a split
        p_left = half_perimeter(*union(lower[left], upper[left]))
        p_right = half_perimeter(*union(lower[~left], upper[~left]))
        expected_tests = (p_left * n_left + p_right * n_right) / parent
        costs[plane] = node_cost + triangle_cost * expected_tests
    positions = low + extent * np.arange(1, bins) / bins
    return Candidates(axis, positions, costs, left_counts, bin_of)


def best_split(lower, upper, bins=BINS, node_cost=NODE_COST, triangle_cost=TRIANGLE_COST):
    """(axis, plane index, cost, candidates) of the cheapest split over both axes, or
    None when no plane separates any two centroids. Ties: the first one (x, then y)."""
    best = None
    for axis in (0, 1):
        candidates = sah_candidates(lower, upper, axis, bins, node_cost, triangle_cost)
        if candidates is None or np.all(np.isnan(candidates.costs)):
            continue
        plane = int(np.nanargmin(candidates.costs))
        cost = float(candidates.costs[plane])
        if best is None or cost < best[2]:
            best = (axis, plane, cost, candidates)
    return best


# ---------------------------------------------------------------------------------------
# The tree
# ---------------------------------------------------------------------------------------

@dataclass
class Node:
    lower: np.ndarray
    upper: np.ndarray
    depth: int                        # the root is 0
    triangles: np.ndarray             # indices of the triangles below this node
    children: list = field(default_factory=list)  # [] for a leaf
    split: tuple = None               # (axis, position) of the plane, for inner nodes

    @property
    def is_leaf(self):
        return not self.children


def build(triangles, bins=BINS, max_leaf=MAX_LEAF, node_cost=NODE_COST,
          triangle_cost=TRIANGLE_COST):
    """The tree over the triangles, as nested Nodes; the root first."""
    lower, upper = triangle_boxes(triangles)

    def build_range(indices, depth):
        box = union(lower[indices], upper[indices])
        node = Node(box[0], box[1], depth, indices)
        count = len(indices)
        if count == 1:
            return node
        split = best_split(lower[indices], upper[indices], bins, node_cost, triangle_cost)
        leaf_cost = triangle_cost * count
        if count <= max_leaf and (split is None or split[2] >= leaf_cost):
            return node
        if split is None:  # all centroids at one point: halve the list
            halves = [indices[:count // 2], indices[count // 2:]]
        else:
            axis, plane, _, candidates = split
            left = candidates.bin_of <= plane
            halves = [indices[left], indices[~left]]
            node.split = (axis, float(candidates.positions[plane]))
        node.children = [build_range(half, depth + 1) for half in halves]
        return node

    return build_range(np.arange(len(lower)), 0)


def nodes_of(root):
    """Every node, depth first."""
    stack, nodes = [root], []
    while stack:
        node = stack.pop()
        nodes.append(node)
        stack.extend(reversed(node.children))
    return nodes


def sah_cost(root, node_cost=NODE_COST, triangle_cost=TRIANGLE_COST):
    """The tree's SAH cost: what a line through the root box pays on average."""
    root_perimeter = half_perimeter(root.lower, root.upper)
    total = 0.0
    for node in nodes_of(root):
        weight = half_perimeter(node.lower, node.upper) / root_perimeter
        total += weight * (triangle_cost * len(node.triangles) if node.is_leaf else node_cost)
    return total


# ---------------------------------------------------------------------------------------
# The figure
# ---------------------------------------------------------------------------------------

def draw_figure(triangles, path=None, bins=BINS, max_leaf=MAX_LEAF):
    """Top: the boxes of depths 1, 2 and 3, then all of them, coloured by depth.
    Bottom: the SAH cost of each candidate plane at the root."""
    import matplotlib
    if path:
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Polygon, Rectangle

    root = build(triangles, bins, max_leaf)
    nodes = nodes_of(root)
    max_depth = max(node.depth for node in nodes)
    colours = plt.get_cmap("viridis")

    def colour(depth):  # up to 0.85 of the map: the last yellows are hard to see
        return colours(0.85 * depth / max(1, max_depth))

    def draw_triangles(axes):
        for corners in triangles:
            axes.add_patch(Polygon(corners, closed=True, facecolor="0.78",
                                   edgecolor="0.5", linewidth=0.4, zorder=1))
        axes.set_xlim(root.lower[0] - 0.3, root.upper[0] + 0.3)
        axes.set_ylim(root.lower[1] - 0.3, root.upper[1] + 0.3)
        axes.set_aspect("equal")
        axes.set_xticks([])
        axes.set_yticks([])

    def draw_box(axes, node, width):
        size = node.upper - node.lower
        axes.add_patch(Rectangle(node.lower, size[0], size[1], fill=False,
                                 edgecolor=colour(node.depth), linewidth=width,
                                 zorder=2 + node.depth))

    def draw_split(axes, node):
        axis, position = node.split
        low, high = node.lower[1 - axis], node.upper[1 - axis]
        ends = ([position, position], [low, high]) if axis == 0 else \
            ([low, high], [position, position])
        axes.plot(*ends, color="crimson", linestyle="--", linewidth=1.4, zorder=40)

    figure = plt.figure(figsize=(13, 7.4))
    grid = figure.add_gridspec(2, 4, height_ratios=[1.0, 1.15], hspace=0.22, wspace=0.08,
                               top=0.93)

    # Top: one level at a time, the planes that made it dashed, then the whole tree.
    for column, depth in enumerate((1, 2, 3)):
        axes = figure.add_subplot(grid[0, column])
        draw_triangles(axes)
        draw_box(axes, root, 1.0)
        level = [node for node in nodes if node.depth == depth]
        for node in level:
            draw_box(axes, node, 2.2)
        for parent in (node for node in nodes if node.depth == depth - 1 and node.split):
            draw_split(axes, parent)
        axes.set_title(f"depth {depth}: {len(level)} boxes", fontsize=11)
    axes = figure.add_subplot(grid[0, 3])
    draw_triangles(axes)
    for node in sorted(nodes, key=lambda n: n.depth):
        draw_box(axes, node, max(0.6, 2.4 - 0.3 * node.depth))
    leaves = sum(node.is_leaf for node in nodes)
    axes.set_title(f"all: depth 0 (dark) to {max_depth} (light)", fontsize=11)

    # Bottom: the root's candidates, the chosen one starred.
    axes = figure.add_subplot(grid[1, 1:3])
    lower, upper = triangle_boxes(triangles)
    chosen_axis, chosen_plane, chosen_cost, _ = best_split(lower, upper, bins)
    for axis, (name, style) in enumerate([("x", "o-"), ("y", "s-")]):
        candidates = sah_candidates(lower, upper, axis, bins)
        axes.plot(candidates.positions, candidates.costs, style, markersize=4,
                  label=f"a plane across {name}, at this {name}")
        if axis == chosen_axis:
            axes.plot(candidates.positions[chosen_plane], chosen_cost, "*",
                      color="crimson", markersize=16, zorder=5,
                      label=f"the cheapest, {chosen_cost:.1f}: depth 1's dashed line")
    axes.set_xlabel("where the candidate plane is (a boundary between two of the "
                    f"{bins} bins)")
    axes.set_ylabel("SAH cost (node visits + triangle tests\nof a line through the root)")
    axes.set_title(f"The root's {bins - 1} candidate planes per axis. Not splitting "
                   f"costs {TRIANGLE_COST * len(triangles):.0f}: every triangle",
                   fontsize=11)
    axes.grid(True, alpha=0.3)
    axes.legend(loc="upper center", fontsize=9)

    figure.suptitle(f"Binned SAH in 2D: {len(triangles)} triangles, "
                    f"{len(nodes) - leaves} inner nodes, {leaves} leaves of at most "
                    f"{max_leaf}, SAH cost of the tree {sah_cost(root):.1f}", fontsize=13)
    if path:
        figure.savefig(path, dpi=120, bbox_inches="tight")
        plt.close(figure)
    else:
        plt.show()


def parse_args(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--triangles", type=int, default=80, help="how many (default 80)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--bins", type=int, default=BINS, help="per axis (default 16)")
    parser.add_argument("--max-leaf", type=int, default=MAX_LEAF,
                        help="most triangles in a leaf (default 4)")
    parser.add_argument("--figure", help="write the figure to this file (else show it)")
    args = parser.parse_args(argv)
    if args.triangles < 2 or args.bins < 2 or args.max_leaf < 1:
        parser.error("need --triangles >= 2, --bins >= 2, --max-leaf >= 1")
    return args


def main(argv=None):
    args = parse_args(argv)
    triangles = random_triangles(args.triangles, args.seed)
    draw_figure(triangles, args.figure, args.bins, args.max_leaf)
    if args.figure:
        print(args.figure)
    return 0


if __name__ == "__main__":
    sys.exit(main())
