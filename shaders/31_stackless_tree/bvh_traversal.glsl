// Finding what a ray hits by walking the bounding volume hierarchy instead of testing
// every triangle: a box that the ray misses rules out every triangle inside it.
// Chapter 31 walks it without a stack: the boxes come in the order the ray's octant
// visits them, and a box the ray misses says where to go on (threaded_tree.h).
//
// What the including shader provides, before #include "bvh_traversal.glsl":
//   - BVH_NODES_BINDING, struct BvhBox, struct BvhGrid and BVH_MAX_LEAF_SIZE (4)
//     (shared.h, which includes bvh_layout.h), and bvhBoxAt(i) and bvhGrid()
//     (scene_memory.glsl);
//   - struct Ray { vec3 origin; vec3 direction; };  (camera.glsl; any length > 0)
//   - bool hitTriangle(Ray ray, uint triangleIndex, float tMin, float tMax,
//                      out float t, out vec2 uv);
//     true when the ray meets triangle `triangleIndex` at tMin < t < tMax. The index
//     counts triangles in leaf order: the host uploads its triangles reordered by
//     Bvh::triangleOrder (inLeafOrder()), so that each leaf is one run of them.
// What it gets:
//   bool bvhNearestHit(Ray ray, float tMin, float tMax,
//                      out uint triangle, out float t, out vec2 uv);
//   bool bvhAnyHit(Ray ray, float tMin, float tMax);
//   uint bvhLoopIterations: traversal loop iterations so far (the caller may reset it).

#ifndef BVH_NODES_BINDING
#error "bvh_traversal.glsl: define BVH_NODES_BINDING (shared.h) before including it"
#endif
#if BVH_MAX_LEAF_SIZE != 4
#error "bvh_traversal.glsl tests a leaf's triangles written out for 4 of them"
#endif


// What the box test returns for a miss, and the farthest a hit may be: a caller's tMax
// of 1e38 or infinity means "no limit", and stays nearer than a miss.
const float BVH_MISS = 3.0e38;
const float BVH_FAR = 1.0e38;
const uint BVH_COUNT_MASK = (1u << BVH_COUNT_BITS) - 1u;  // a leaf's count in BvhBox::next

// Iterations of the traversal loop, added up over all calls: the number to watch on
// Mesa 22's llvmpipe, which runs invocations in groups of 8 and stops a group, silently,
// after 65535 loop iterations in all (the slowest of the 8 decides how many a loop
// takes). The course measures that limit at run time (common/course/loop_budget.h).
uint bvhLoopIterations = 0u;

// --8<-- [start:ray]
// The ray as the box test wants it, worked out once per ray rather than once per box.
struct BvhRay {
    vec3 origin;
    vec3 inverseDirection;  // 1 / direction: a multiply per plane instead of a divide
    bvec3 negative;         // which way the ray runs along each axis
};

BvhRay bvhRay(Ray ray) {
    // A direction component of 0 would give 1/0 = infinity, and a box face through the
    // origin 0 * infinity = NaN. A tiny positive stand-in keeps everything finite: the
    // ray is then between a box's two planes for t from -1e30 to 1e30, or for none.
    const float tiny = 1e-30;
    vec3 direction = mix(ray.direction, vec3(tiny), lessThan(abs(ray.direction), vec3(tiny)));
    vec3 inverseDirection = 1.0 / direction;
    return BvhRay(ray.origin, inverseDirection, lessThan(inverseDirection, vec3(0.0)));
}

// The same ray with the grid's steps as its unit of length along each axis: a point p
// of the world is (p - origin) / step there. Distances t along the ray stay the same,
// so a box's planes, whole steps, go into the slab test as they are.
BvhRay onGrid(BvhRay ray, BvhGrid grid) {
    return BvhRay((ray.origin - grid.origin) / grid.step, ray.inverseDirection * grid.step,
                  ray.negative);
}

// A box's near and far corners, in steps of the grid.
void boxCorners(BvhBox box, out vec3 nearCorner, out vec3 farCorner) {
    nearCorner = vec3(uvec3(box.nearXY & 0xFFFFu, box.nearXY >> 16u, box.nearZFarX & 0xFFFFu));
    farCorner = vec3(uvec3(box.nearZFarX >> 16u, box.farYZ & 0xFFFFu, box.farYZ >> 16u));
}
// --8<-- [end:ray]

// --8<-- [start:slab]
// Where the ray enters the box, if it is inside the box somewhere between tMin and tMax;
// BVH_MISS if not. The slab test: along each axis the ray is between the box's two
// planes from tNear to tFar; it is in the box where it is between all three pairs.
// Chapter 13 picked the near planes by the direction's signs for each box; chapter 31's
// boxes come with them picked, for the octant's rays (BvhBox). (So a box with its near
// plane beyond its far one is missed: tFar < tNear.)
float bvhEnterBox(BvhRay ray, vec3 nearPlanes, vec3 farPlanes, float tMin, float tMax) {
    vec3 tNear = (nearPlanes - ray.origin) * ray.inverseDirection;
    vec3 tFar = (farPlanes - ray.origin) * ray.inverseDirection;
    float enter = max(max(tNear.x, tNear.y), max(tNear.z, tMin));
    float exit = min(min(tFar.x, tFar.y), min(tFar.z, tMax));
    // Rounding could make a ray that grazes an edge of the box miss it by an ulp, and
    // lose a triangle on that edge; a slightly later exit keeps the test conservative.
    return enter <= exit * 1.0000004 ? enter : BVH_MISS;
}
// --8<-- [end:slab]

// --8<-- [start:triangle]
// One triangle of a leaf: a nearer hit than the nearest so far replaces it.
void bvhTestTriangle(Ray ray, uint index, float tMin, inout bool found, inout uint triangle,
                     inout float t, inout vec2 uv) {
    float tHit;
    vec2 uvHit;
    if (hitTriangle(ray, index, tMin, t, tHit, uvHit)) {
        found = true;
        triangle = index;
        t = tHit;
        uv = uvHit;
    }
}
// --8<-- [end:triangle]

// --8<-- [start:traverse]
// The nearest hit (anyHit == false) or any hit (true) between tMin and tMax.
bool bvhTraverse(Ray ray, float tMin, float tMax, bool anyHit, out uint triangle,
                 out float t, out vec2 uv) {
    BvhGrid grid = bvhGrid();
    BvhRay gridRay = onGrid(bvhRay(ray), grid);
    bool found = false;
    triangle = 0u;
    t = min(tMax, BVH_FAR);  // only hits nearer than this count; it shrinks with each hit
    uv = vec2(0.0);

    // The boxes in the order of the ray's octant, from the first to the last.
    uint octant = (gridRay.negative.x ? 1u : 0u) | (gridRay.negative.y ? 2u : 0u) |
                  (gridRay.negative.z ? 4u : 0u);
    uint next = octant * grid.boxesPerOrder, end = next + grid.boxesPerOrder;
    for (;;) {
        // 1. Box after box until the ray enters a leaf's, or the order ends. A box the
        //    ray enters before the nearest hit so far: a node's children come next. A
        //    box it misses (or enters only behind that hit): what is inside is skipped.
        //    One test a turn, no stack, no sorting: the order did the sorting. As in
        //    chapter 21, lanes that reach a leaf wait for the others ("while-while").
        uint leaf = 0u;
        while (next != end) {
            ++bvhLoopIterations;
            BvhBox box = bvhBoxAt(next);
            vec3 nearCorner, farCorner;
            boxCorners(box, nearCorner, farCorner);
            bool enters = bvhEnterBox(gridRay, nearCorner, farCorner, tMin, t) < t;
            bool isLeaf = (box.next & BVH_COUNT_MASK) != 0u;
            next = enters || isLeaf ? next + 1u : box.next >> BVH_COUNT_BITS;
            if (enters && isLeaf) {
                leaf = box.next;
                break;
            }
        }
        if (leaf == 0u) break;
        // 2. A leaf: test its triangles, written out rather than looped (a GL with a loop
        //    limit, Mesa 22's llvmpipe, counts every iteration against it).
        ++bvhLoopIterations;
        uint first = leaf >> BVH_COUNT_BITS, count = leaf & BVH_COUNT_MASK;
        bvhTestTriangle(ray, first, tMin, found, triangle, t, uv);
        if (count > 1u) bvhTestTriangle(ray, first + 1u, tMin, found, triangle, t, uv);
        if (count > 2u) bvhTestTriangle(ray, first + 2u, tMin, found, triangle, t, uv);
        if (count > 3u) bvhTestTriangle(ray, first + 3u, tMin, found, triangle, t, uv);
        if (found && anyHit) return true;  // a shadow ray needs no more
    }
    return found;
}
// --8<-- [end:traverse]

// --8<-- [start:queries]
// The nearest surface along the ray between tMin and tMax: which triangle (leaf order),
// how far, and where on it (barycentric u, v).
bool bvhNearestHit(Ray ray, float tMin, float tMax, out uint triangle, out float t,
                   out vec2 uv) {
    return bvhTraverse(ray, tMin, tMax, false, triangle, t, uv);
}

// Is anything in the way between tMin and tMax? The first hit ends the search.
bool bvhAnyHit(Ray ray, float tMin, float tMax) {
    uint triangle;
    float t;
    vec2 uv;
    return bvhTraverse(ray, tMin, tMax, true, triangle, t, uv);
}
// --8<-- [end:queries]
