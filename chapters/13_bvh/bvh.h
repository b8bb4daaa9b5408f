// A bounding volume hierarchy over a triangle mesh, built on the CPU by splitting at the
// median and flattened into the node array the GPU traverses. No GL here: the
// chapter uploads `nodes` into a storage buffer and its triangles in `triangleOrder`.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "bvh_layout.h"  // gpu::BvhNode, BVH_MAX_LEAF_SIZE, BVH_MAX_DEPTH

// --8<-- [start:bvh]
struct Bvh {
    std::vector<gpu::BvhNode> nodes;  // depth first; nodes[0] is the root
    // The triangles in leaf order: leaf triangle i is input triangle triangleOrder[i].
    // A leaf's triangles are one range of this order, so a node needs only (first, count).
    std::vector<uint32_t> triangleOrder;
};
// --8<-- [end:bvh]

// Builds the tree over the triangles (triangleIndices[3 * i + k] is corner k of
// triangle i, an index into positions). Deterministic: the same input gives
// byte-identical nodes and order. Zero-area triangles, repeated triangles and any number
// of triangles from 0 up are fine. Throws course::Failure(BadInput) for an index out of
// range or a position that is not finite (the message says which). A leaf holds 1 to
// BVH_MAX_LEAF_SIZE triangles, and every split halves its range, so no leaf is more than
// log2(n / BVH_MAX_LEAF_SIZE), rounded up, node fetches down: within BVH_MAX_DEPTH.
Bvh buildBvh(const std::vector<glm::vec3>& positions,
             const std::vector<uint32_t>& triangleIndices);
