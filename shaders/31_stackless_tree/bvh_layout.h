// The bounding volume hierarchy as the GPU reads it: one struct and a few numbers that
// the C++ builder (bvh.cpp) and the GLSL traversal (bvh_traversal.glsl) must agree on.
// Both sides read this one file, like shared.h (which includes it): GLSL sees the struct
// as it is, C++ sees it in namespace gpu with glm's types, and the includes it needs
// inside `#ifdef __cplusplus`, which the course's shader loader passes over.
#ifndef COURSE_BVH_LAYOUT_H
#define COURSE_BVH_LAYOUT_H

// --8<-- [start:limits]
// The most triangles in one leaf. The traversal tests them one after the other, written
// out rather than in a loop: Mesa 22's llvmpipe stops a shader invocation after 65535
// loop iterations, and counts every iteration of every loop (bvh_traversal.glsl).
#define BVH_MAX_LEAF_SIZE 4

// The deepest leaf is found after at most this many node fetches: buildBvh() switches
// to halving splits when a subtree would get deeper (bvh.cpp). (Chapter 21's stack had
// as many entries; chapter 31's walk has no stack, and the limit keeps the host's
// recursion over the tree shallow.)
#define BVH_MAX_DEPTH 64

// A box's `next` (BvhBox, below) holds an index above the low BVH_COUNT_BITS bits and
// a leaf's triangle count in them. So a leaf holds fewer than 2^3 triangles, and the
// boxes number fewer than 2^29 (threadTree() refuses more).
#define BVH_COUNT_BITS 3u
// --8<-- [end:limits]

#ifdef __cplusplus
#include <cstddef>      // offsetof, for the static_asserts
#include <glm/glm.hpp>  // the vector types
namespace gpu {
using uint = glm::uint;
using vec3 = glm::vec3;
#endif

// --8<-- [start:node]
// One node of the tree: the boxes of BOTH its children, so that one 64-byte fetch gives
// the traversal two boxes to test, and says where each child is:
//   xxxCount == 0: the child is a node of its own, bvhNodes[xxxIndex];
//   xxxCount >  0: the child is a leaf, the triangles xxxIndex ... xxxIndex + xxxCount - 1
//                  (triangles are stored in leaf order: see Bvh::triangleOrder).
// Node 0 is the root; nodes are stored depth first, so a node's first child (if it is a
// node) is the next one in the array. The root's own box is the union of its children's.
//
// std430 aligns a vec3 to 16 bytes but gives it only 12, so the uint after each vec3
// fills its fourth slot: exactly where C++ puts a uint after a 12-byte glm::vec3. No
// padding, no bit tricks, four aligned 16-byte loads.
//
// A child that does not exist (the second child of a root whose whole mesh fits in one
// leaf, or both children of an empty mesh) has an empty box, min > max, that every ray
// misses (the slab test in bvh_traversal.glsl), and index 0, count 0.
struct BvhNode {
    vec3 leftMin;    // the left child's box: lower corner ...
    uint leftIndex;  // node index (inner child) or first triangle (leaf)
    vec3 leftMax;    // ... and upper corner
    uint leftCount;  // 0 for an inner child, else the number of triangles in the leaf
    vec3 rightMin;   // the same for the right child
    uint rightIndex;
    vec3 rightMax;
    uint rightCount;
};
// --8<-- [end:node]

// --8<-- [start:box]
// Chapter 31 walks the tree without a stack (threaded_tree.h): the node's boxes laid
// out in the order a ray visits them, one order for each octant of ray directions.
// A box is 16 bytes, one texel. Its planes are whole steps of a grid (BvhGrid) rounded
// outwards, 16 bits each, and in the order the octant's rays meet them: the near
// corner's, then the far corner's (along an axis the rays run down, the upper plane is
// the near one). `next` says what the box is:
//   next & 7 >  0: a leaf, the triangles (next >> 3) ... (next >> 3) + (next & 7) - 1;
//   next & 7 == 0: a node; its children's boxes follow it, and a ray that misses it
//                  goes on at box next >> 3, the first after its subtree.
struct BvhBox {
    uint nearXY;     // the near corner's x (low 16 bits) and y (high 16 bits)
    uint nearZFarX;  // the near corner's z and the far corner's x
    uint farYZ;      // the far corner's y and z
    uint next;
};

// The grid, in the first BVH_GRID_BOXES boxes' place: a corner q (whole steps) is at
// origin + q * step. Then come the 8 orders, boxesPerOrder boxes each: the order for
// octant k (bit a set: the ray runs towards -a) starts at box k * boxesPerOrder.
struct BvhGrid {
    vec3 origin;
    uint boxesPerOrder;
    vec3 step;
    uint unused;
};
#define BVH_GRID_BOXES 2
// --8<-- [end:box]

#ifdef __cplusplus
// The offsets GLSL's std430 rules give; a C++ struct that differs would scramble the
// tree silently, so the compiler checks.
static_assert(sizeof(BvhNode) == 64, "std430 BvhNode: four 16-byte rows");
static_assert(sizeof(BvhBox) == 16 && sizeof(BvhGrid) == 32, "std430 BvhBox, BvhGrid");
static_assert(BVH_MAX_LEAF_SIZE < (1u << BVH_COUNT_BITS), "a leaf's count fits its bits");
static_assert(offsetof(BvhNode, leftIndex) == 12 && offsetof(BvhNode, leftMax) == 16 &&
                  offsetof(BvhNode, leftCount) == 28 && offsetof(BvhNode, rightMin) == 32 &&
                  offsetof(BvhNode, rightIndex) == 44 && offsetof(BvhNode, rightMax) == 48 &&
                  offsetof(BvhNode, rightCount) == 60,
              "std430 BvhNode: each uint fills the fourth slot of the vec3 before it");
}  // namespace gpu
#endif

#endif
