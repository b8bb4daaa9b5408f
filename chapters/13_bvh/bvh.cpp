#include "bvh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "course/error.h"

namespace {

using glm::vec3;

// --8<-- [start:box]
// An axis-aligned box. A new box is empty, min > max, so that growing it by anything
// gives exactly that thing; an empty box is also what the GPU misses (bvh_layout.h).
struct Box {
    vec3 min{std::numeric_limits<float>::max()};
    vec3 max{-std::numeric_limits<float>::max()};

    void grow(const vec3& point) {
        min = glm::min(min, point);
        max = glm::max(max, point);
    }
    void grow(const Box& box) {
        min = glm::min(min, box.min);
        max = glm::max(max, box.max);
    }
};
// --8<-- [end:box]

// One triangle while the tree is built: its box and its index in the input. The
// builder sorts these records, not the triangles: 28 bytes each, read in order.
struct TriangleRecord {
    Box box;
    uint32_t triangle;
    // The centre of the box stands for the triangle when splitting. (Each half first:
    // min + max could overflow where min / 2 + max / 2 cannot.)
    vec3 centroid() const { return box.min * 0.5f + box.max * 0.5f; }
};

// What a child slot of a node holds: the child's box and where it is (bvh_layout.h).
struct Child {
    Box box;
    uint32_t index = 0;  // a node, or the first triangle of a leaf
    uint32_t count = 0;  // 0: a node; otherwise a leaf of `count` triangles
};

// Every split halves its range (the median split below), so a leaf of n < 2^32 triangles
// is at most 32 node fetches down: the traversal's stack must have room for that.
static_assert(BVH_MAX_DEPTH >= 32, "halving splits of 2^32 triangles need 32 levels");

// --8<-- [start:median]
// The triangles whose centroids are the lower half along the centroids' longest axis
// go left: both children get half (ties broken by input index, so it is deterministic).
// nth_element puts the middle record where a sort would, the smaller ones before it and
// the larger after, in time proportional to the range: no full sort is needed.
uint32_t medianSplit(std::vector<TriangleRecord>& records, uint32_t begin, uint32_t end,
                     const Box& centroids) {
    const vec3 extent = centroids.max - centroids.min;
    int axis = 0;
    for (int a = 1; a < 3; ++a)
        if (extent[a] > extent[axis]) axis = a;
    const uint32_t middle = begin + (end - begin) / 2;
    std::nth_element(records.begin() + begin, records.begin() + middle,
                     records.begin() + end,
                     [axis](const TriangleRecord& a, const TriangleRecord& b) {
                         float ca = a.centroid()[axis], cb = b.centroid()[axis];
                         return ca < cb || (ca == cb && a.triangle < b.triangle);
                     });
    return middle;
}
// --8<-- [end:median]

// --8<-- [start:build]
// Builds the subtree of records [begin, end), its nodes appended to `nodes`, and returns
// the child slot that points at it.
Child build(std::vector<TriangleRecord>& records, uint32_t begin, uint32_t end,
            std::vector<gpu::BvhNode>& nodes) {
    Box box, centroids;  // of the triangles, and of their centroids
    for (uint32_t i = begin; i < end; ++i) {
        box.grow(records[i].box);
        centroids.grow(records[i].centroid());
    }

    // 1. A leaf, if the range is small enough: its triangles are the records' range
    //    (the records' order becomes the leaf order).
    if (end - begin <= BVH_MAX_LEAF_SIZE) return {box, begin, end - begin};

    // 2. Otherwise two halves: the triangles with the lower centroids along the longest
    //    side go left, the others right.
    const uint32_t middle = medianSplit(records, begin, end, centroids);

    // 3. The node goes into the array before its children: depth first, root at 0.
    const uint32_t nodeIndex = uint32_t(nodes.size());
    nodes.emplace_back();
    Child left = build(records, begin, middle, nodes);
    Child right = build(records, middle, end, nodes);
    nodes[nodeIndex] = {left.box.min,  left.index,  left.box.max,  left.count,
                        right.box.min, right.index, right.box.max, right.count};
    return {box, nodeIndex, 0};
}
// --8<-- [end:build]

[[noreturn]] void badInput(const std::string& what) {
    course::fail(course::ExitCode::BadInput, "buildBvh: " + what);
}

}  // namespace

Bvh buildBvh(const std::vector<vec3>& positions, const std::vector<uint32_t>& triangleIndices) {
    if (triangleIndices.size() % 3 != 0)
        badInput(std::to_string(triangleIndices.size()) +
                 " triangle indices: not 3 per triangle");
    const size_t triangleCount = triangleIndices.size() / 3;
    if (triangleCount >= std::numeric_limits<uint32_t>::max())
        badInput(std::to_string(triangleCount) + " triangles: more than 32-bit indices hold");

    // 1. A record per triangle: its box, from its three corners.
    std::vector<TriangleRecord> records(triangleCount);
    for (size_t i = 0; i < triangleCount; ++i) {
        records[i].triangle = uint32_t(i);
        for (int corner = 0; corner < 3; ++corner) {
            const uint32_t index = triangleIndices[3 * i + corner];
            if (index >= positions.size())
                badInput("triangle " + std::to_string(i) + " corner " + std::to_string(corner) +
                         ": index " + std::to_string(index) + ", but there are only " +
                         std::to_string(positions.size()) + " positions");
            const vec3& p = positions[index];
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                badInput("position " + std::to_string(index) + " (triangle " +
                         std::to_string(i) + ") is not a finite number");
            records[i].box.grow(p);
        }
    }

    // 2. The tree, depth first from the root.
    Bvh bvh;
    bvh.nodes.reserve(triangleCount == 0 ? 1 : 2 * triangleCount / BVH_MAX_LEAF_SIZE + 1);
    if (triangleCount == 0) {  // no triangles: a root whose two children do not exist
        bvh.nodes.push_back({Box{}.min, 0, Box{}.max, 0, Box{}.min, 0, Box{}.max, 0});
    } else {
        Child root = build(records, 0, uint32_t(triangleCount), bvh.nodes);
        if (root.count > 0) {
            // The whole mesh is one leaf: the root node holds it and an empty child,
            // because the traversal always starts with a node.
            bvh.nodes.push_back({root.box.min, root.index, root.box.max, root.count,
                                 Box{}.min, 0, Box{}.max, 0});
        }
    }

    // 3. The leaf order.
    bvh.triangleOrder.resize(triangleCount);
    for (size_t i = 0; i < triangleCount; ++i) bvh.triangleOrder[i] = records[i].triangle;
    return bvh;
}
