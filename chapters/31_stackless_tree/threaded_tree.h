// The tree as chapter 31 walks it, without a stack. The boxes of Bvh::nodes are laid
// out in the order a ray visits them, depth first with the nearer child first, and each
// box says where the walk goes when the ray misses it: the box after its subtree
// (a "threaded" tree). Which child is nearer depends on the ray's direction, so there is
// one such order for each of the 8 octants of directions. Each box is one 16-byte texel:
// its planes rounded outwards onto a grid of 65 536 steps across the mesh.
#pragma once
#include <vector>

#include "bvh.h"  // Bvh, gpu::BvhBox and gpu::BvhGrid (bvh_layout.h)

// What the GPU reads (BVH_NODES_BINDING): the grid in the first BVH_GRID_BOXES entries,
// then the 8 orders, BvhGrid::boxesPerOrder boxes each. Exit code 3 for a mesh whose
// boxes would not fit the 29 bits an index has.
std::vector<gpu::BvhBox> threadTree(const Bvh& bvh);
