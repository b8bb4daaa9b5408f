#include "threaded_tree.h"

#include <cstring>
#include <string>
#include <utility>

#include "course/error.h"

namespace {

using glm::vec3;

// --8<-- [start:grid]
// The grid the boxes are rounded onto: 65 532 steps across the mesh's box on each axis,
// and a step and a half to spare at each end, so that rounding outwards stays within
// 0 ... 65 535. An axis along which the mesh is flat still gets steps of a useful size
// (a thousandth of its longest side's), not of zero.
gpu::BvhGrid gridOver(vec3 lower, vec3 upper, uint32_t boxesPerOrder) {
    vec3 extent = upper - lower;
    float longest = glm::max(glm::max(extent.x, extent.y), glm::max(extent.z, 1e-30f));
    vec3 step = glm::max(extent, vec3(1e-3f * longest)) / 65532.0f;
    return gpu::BvhGrid{lower - 1.5f * step, boxesPerOrder, step, 0u};
}

// A box's planes as whole steps of the grid, rounded outwards: the lower corner down,
// the upper up, and one step more each way, so that rounding in the GPU's arithmetic
// cannot lose a ray that grazes the box. Then in the order the octant's rays meet them:
// along an axis the rays run down (bit k of `octant` for axis k), the upper plane
// first. Two 16-bit numbers to a uint.
gpu::BvhBox roundOntoGrid(const gpu::BvhGrid& grid, vec3 lower, vec3 upper, int octant,
                          uint32_t next) {
    glm::uvec3 low(65535u), high(0u);  // an empty box (min > max) stays empty: missed
    if (lower.x <= upper.x) {
        vec3 below = glm::floor((lower - grid.origin) / grid.step) - 1.0f;
        vec3 above = glm::ceil((upper - grid.origin) / grid.step) + 1.0f;
        low = glm::uvec3(glm::clamp(below, 0.0f, 65535.0f));
        high = glm::uvec3(glm::clamp(above, 0.0f, 65535.0f));
    }
    glm::uvec3 near = low, far = high;
    for (int axis = 0; axis < 3; ++axis)
        if ((octant >> axis) & 1) std::swap(near[axis], far[axis]);
    return gpu::BvhBox{near.x | (near.y << 16), near.z | (far.x << 16), far.y | (far.z << 16),
                       next};
}
// --8<-- [end:grid]

// A child as the node stores it: its box, and (index, count) as in gpu::BvhNode.
struct Child {
    vec3 lower, upper;
    uint32_t index, count;
};

// --8<-- [start:order]
// Which of a node's children a ray of this octant visits first (bit k of `octant`: the
// ray runs towards -axis k): the one whose centre comes first along the axis on which
// the two centres lie furthest apart, going the ray's way along it.
bool leftFirst(const gpu::BvhNode& node, int octant) {
    vec3 left = node.leftMin + node.leftMax, right = node.rightMin + node.rightMax;
    vec3 apart = glm::abs(left - right);
    int axis = apart.x >= apart.y && apart.x >= apart.z ? 0 : apart.y >= apart.z ? 1 : 2;
    bool towardsMinus = (octant >> axis) & 1;
    return (left[axis] <= right[axis]) != towardsMinus;
}

void layOut(const Bvh& bvh, const gpu::BvhGrid& grid, const Child& child, int octant,
            std::vector<gpu::BvhBox>& boxes);

// Lays out a node's two children's subtrees in the octant's order, nearer first.
void layOutChildren(const Bvh& bvh, const gpu::BvhGrid& grid, const gpu::BvhNode& node,
                    int octant, std::vector<gpu::BvhBox>& boxes) {
    Child left{node.leftMin, node.leftMax, node.leftIndex, node.leftCount};
    Child right{node.rightMin, node.rightMax, node.rightIndex, node.rightCount};
    bool first = leftFirst(node, octant);
    layOut(bvh, grid, first ? left : right, octant, boxes);
    layOut(bvh, grid, first ? right : left, octant, boxes);
}

// Lays out a child's subtree in the octant's order, after what `boxes` holds: the
// child's box, then (for a node) its children's subtrees, nearer first. A leaf says
// which triangles it holds; a node, where its subtree ends: the walk goes on there
// when the ray misses the node's box (after a leaf, it simply goes on to the next box).
void layOut(const Bvh& bvh, const gpu::BvhGrid& grid, const Child& child, int octant,
            std::vector<gpu::BvhBox>& boxes) {
    size_t at = boxes.size();
    bool leaf = child.count > 0, empty = !(child.lower.x <= child.upper.x);
    boxes.push_back(roundOntoGrid(grid, child.lower, child.upper, octant,
                                  leaf ? (child.index << BVH_COUNT_BITS) | child.count : 0u));
    if (!leaf && !empty) layOutChildren(bvh, grid, bvh.nodes[child.index], octant, boxes);
    if (!leaf) boxes[at].next = uint32_t(boxes.size() - BVH_GRID_BOXES) << BVH_COUNT_BITS;
}
// --8<-- [end:order]

}  // namespace

// --8<-- [start:thread]
std::vector<gpu::BvhBox> threadTree(const Bvh& bvh) {
    const gpu::BvhNode& root = bvh.nodes[0];
    // The root's own box is not tested: each order starts with its children's subtrees.
    const size_t boxesPerOrder = 2 * bvh.nodes.size();
    if (8 * boxesPerOrder >= (size_t(1) << (32 - BVH_COUNT_BITS)))
        course::fail(course::ExitCode::BadInput,
                     "threadTree: " + std::to_string(bvh.nodes.size()) +
                         " nodes are too many: 8 orders of their boxes need indices of more "
                         "than " + std::to_string(32 - BVH_COUNT_BITS) + " bits");
    vec3 lower = glm::min(root.leftMin, root.rightMin);
    vec3 upper = glm::max(root.leftMax, root.rightMax);
    if (!(lower.x <= upper.x)) lower = upper = vec3(0.0f);  // no triangles: no boxes hit
    gpu::BvhGrid grid = gridOver(lower, upper, uint32_t(boxesPerOrder));

    std::vector<gpu::BvhBox> boxes(BVH_GRID_BOXES);
    static_assert(sizeof(grid) == BVH_GRID_BOXES * sizeof(gpu::BvhBox), "the grid's boxes");
    std::memcpy(boxes.data(), &grid, sizeof(grid));
    boxes.reserve(BVH_GRID_BOXES + 8 * boxesPerOrder);
    for (int octant = 0; octant < 8; ++octant) layOutChildren(bvh, grid, root, octant, boxes);
    return boxes;
}
// --8<-- [end:thread]
