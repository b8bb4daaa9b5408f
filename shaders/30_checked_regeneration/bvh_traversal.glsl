// Finding what a ray hits by walking the bounding volume hierarchy instead of testing
// every triangle: a box that the ray misses rules out every triangle inside it.
//
// What the including shader provides, before #include "bvh_traversal.glsl":
//   - BVH_NODES_BINDING, struct BvhNode, BVH_MAX_LEAF_SIZE (4) and BVH_STACK_SIZE
//     (shared.h, which includes bvh_layout.h);
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
// --8<-- [end:ray]

// --8<-- [start:slab]
// Where the ray enters the box, if it is inside the box somewhere between tMin and tMax;
// BVH_MISS if not. The slab test: along each axis the ray is between the box's two
// planes from tNear to tFar; it is in the box where it is between all three pairs.
float bvhEnterBox(BvhRay ray, vec3 boxMin, vec3 boxMax, float tMin, float tMax) {
    // Running towards -x, the ray meets the max plane first: the direction's signs
    // pick the near planes. (So a box with min > max is missed: tFar < tNear.)
    vec3 nearPlanes = mix(boxMin, boxMax, ray.negative);
    vec3 farPlanes = mix(boxMax, boxMin, ray.negative);
    vec3 tNear = (nearPlanes - ray.origin) * ray.inverseDirection;
    vec3 tFar = (farPlanes - ray.origin) * ray.inverseDirection;
    float enter = max(max(tNear.x, tNear.y), max(tNear.z, tMin));
    float exit = min(min(tFar.x, tFar.y), min(tFar.z, tMax));
    // Rounding could make a ray that grazes an edge of the box miss it by an ulp, and
    // lose a triangle on that edge; a slightly later exit keeps the test conservative.
    return enter <= exit * 1.0000004 ? enter : BVH_MISS;
}
// --8<-- [end:slab]

// --8<-- [start:pack]
// A child (index, count) as one uint and back, for the stack: llvmpipe reads and writes
// an array element that each lane picks for itself one lane at a time, so every number
// fewer on the stack saves time (5% on the teapot, measured by hand on llvmpipe).
uint bvhPackChild(uvec2 child) { return (child.x << BVH_COUNT_BITS) | child.y; }
uvec2 bvhUnpackChild(uint entry) {
    return uvec2(entry >> BVH_COUNT_BITS, entry & ((1u << BVH_COUNT_BITS) - 1u));
}
// --8<-- [end:pack]

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
    BvhRay boxRay = bvhRay(ray);
    bool found = false;
    triangle = 0u;
    t = min(tMax, BVH_FAR);  // only hits nearer than this count; it shrinks with each hit
    uv = vec2(0.0);

    // What is visited next, and what was put aside for later, with where the ray enters
    // it: a child as the node stores it, (index, count): count 0 for a node, the number
    // of triangles for a leaf.
    uvec2 current = uvec2(0u, 0u);  // the root, node 0
    bool haveCurrent = true;
    uint stack[BVH_STACK_SIZE];  // bvhPackChild
    float stackEnter[BVH_STACK_SIZE];
    int stackSize = 0;

    for (;;) {
        // 1. Down the tree, node after node, until the current child is a leaf or there
        //    is none. Chapter 18 did a node or a leaf per turn of one loop: in a SIMD
        //    group some lanes at a node and some at a leaf run both, masked. Here lanes
        //    that reach a leaf wait for the others, and all then test their leaves
        //    together (Aila and Laine's "while-while" traversal, 2009). A child the ray
        //    misses, or enters only behind the nearest hit so far, is out; the nearer
        //    goes first, the farther is put aside.
        while (haveCurrent && current.y == 0u) {
            ++bvhLoopIterations;
            BvhNode node = bvhNodeAt(current.x);
            float enterLeft = bvhEnterBox(boxRay, node.leftMin, node.leftMax, tMin, t);
            float enterRight = bvhEnterBox(boxRay, node.rightMin, node.rightMax, tMin, t);
            uvec2 left = uvec2(node.leftIndex, node.leftCount);
            uvec2 right = uvec2(node.rightIndex, node.rightCount);
            bool leftFirst = enterLeft <= enterRight;
            uvec2 nearChild = leftFirst ? left : right, farChild = leftFirst ? right : left;
            float enterNear = min(enterLeft, enterRight);
            float enterFar = max(enterLeft, enterRight);
            haveCurrent = enterNear < t;
            if (haveCurrent) current = nearChild;
            if (enterFar < t && stackSize < BVH_STACK_SIZE) {
                stack[stackSize] = bvhPackChild(farChild);
                stackEnter[stackSize] = enterFar;
                ++stackSize;
            }
        }
        // 2. A leaf: test its triangles, written out rather than looped (a GL with a loop
        //    limit, Mesa 22's llvmpipe, counts every iteration against it).
        if (haveCurrent) {
            ++bvhLoopIterations;
            uint first = current.x, count = current.y;
            bvhTestTriangle(ray, first, tMin, found, triangle, t, uv);
            if (count > 1u) bvhTestTriangle(ray, first + 1u, tMin, found, triangle, t, uv);
            if (count > 2u) bvhTestTriangle(ray, first + 2u, tMin, found, triangle, t, uv);
            if (count > 3u) bvhTestTriangle(ray, first + 3u, tMin, found, triangle, t, uv);
            if (found && anyHit) return true;  // a shadow ray needs no more
        }
        // 3. Then the child put aside last that the ray enters before the nearest hit
        //    (the stack never overflows: the builder keeps the tree within
        //    BVH_STACK_SIZE levels).
        haveCurrent = false;
        while (stackSize > 0 && !haveCurrent) {
            --stackSize;
            haveCurrent = stackEnter[stackSize] < t;
            current = bvhUnpackChild(stack[stackSize]);
        }
        if (!haveCurrent) break;
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
