// A bounding volume hierarchy over a triangle mesh, built on the CPU with the surface
// area heuristic and flattened into the node array the GPU traverses. No GL here: the
// chapter uploads `nodes` into a storage buffer and its triangles in `triangleOrder`.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "bvh_layout.h"  // gpu::BvhNode, BVH_MAX_LEAF_SIZE, BVH_MAX_DEPTH

namespace course {
class Stats;
}

// --8<-- [start:options]
// How the tree is built. The defaults are what the chapter uses.
struct BvhOptions {
    // A leaf holds 1 ... maxLeafSize triangles (at most BVH_MAX_LEAF_SIZE, as many as
    // the traversal tests). Up to this size a range becomes a leaf when the SAH says
    // that testing its triangles is cheaper than splitting it.
    int maxLeafSize = BVH_MAX_LEAF_SIZE;
    // Candidate split planes: binCount - 1 per axis, between binCount equal bins of the
    // centroids' extent, on all three axes (or only the longest one: allAxes = false).
    int binCount = 16;
    bool allAxes = true;
    // The SAH's prices: visiting a node (one fetch, two box tests) and testing one
    // triangle. Only their ratio matters for the shape of the tree.
    float nodeCost = 1.0f;
    float triangleCost = 1.0f;
    // How a leaf is priced. Chapter 14 priced it by the triangles it holds (true). The
    // traversal tests a leaf's triangles written out, BVH_MAX_LEAF_SIZE of them, and a
    // SIMD group runs the third and fourth tests if any of its lanes' leaves has that
    // many: a lane's leaf of one costs about what a leaf of four does. Priced so
    // (false), small ranges stay whole leaves and the tree has fewer nodes to fetch.
    bool leavesByCount = false;
    // No leaf deeper than this many node fetches (the traversal's stack size).
    int maxDepth = BVH_MAX_DEPTH;
};
// --8<-- [end:options]

// What was built, for --verbose, --json and the book.
struct BvhStats {
    size_t triangleCount = 0;
    size_t nodeCount = 0;      // entries of Bvh::nodes (inner nodes; the root is one)
    size_t leafCount = 0;
    int maxDepth = 0;          // node fetches to reach the deepest leaf
    int maxLeafSize = 0;       // triangles in the fullest leaf
    size_t depthLimitedSplits = 0;  // halving splits forced by maxDepth (normally 0)
    // The SAH cost of the whole tree: sum over nodes of nodeCost * area / rootArea plus
    // sum over leaves of triangleCost * triangles * area / rootArea. The expected cost
    // of a ray that crosses the root box; brute force would cost triangleCost * n.
    double sahCost = 0.0;
    double buildMilliseconds = 0.0;
    size_t memoryBytes = 0;    // nodes and triangleOrder
};

// --8<-- [start:bvh]
struct Bvh {
    std::vector<gpu::BvhNode> nodes;  // depth first; nodes[0] is the root
    // The triangles in leaf order: leaf triangle i is input triangle triangleOrder[i].
    // A leaf's triangles are one range of this order, so a node needs only (first, count).
    std::vector<uint32_t> triangleOrder;
    BvhStats stats;
};
// --8<-- [end:bvh]

// Builds the tree over the triangles (triangleIndices[3 * i + k] is corner k of
// triangle i, an index into positions). Deterministic: the same input and options give
// byte-identical nodes and order. Zero-area triangles, repeated triangles and any number
// of triangles from 0 up are fine. Throws course::Failure(BadInput) for an index out of
// range, a position that is not finite, or options out of range (the message says which).
Bvh buildBvh(const std::vector<glm::vec3>& positions,
             const std::vector<uint32_t>& triangleIndices, const BvhOptions& options = {});

// One line for --verbose, e.g. "BVH: 6320 triangles -> 1937 nodes, 1938 leaves of at most
// 4 triangles, depth 14, SAH cost 29.0, 0.1 MiB, built in 8 ms".
std::string describeBvh(const BvhStats& stats);
// The stats as --json fields: bvh_build_ms, bvh_nodes, bvh_leaves, bvh_max_depth,
// bvh_sah_cost, bvh_bytes.
void recordBvhStats(const BvhStats& stats, course::Stats& json);
