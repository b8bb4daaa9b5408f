// Shared by the BVH tests of every tree (bvh_tests.cmake), on the CPU and on the GPU:
// test meshes made in C++, a seeded random generator, and C++ ports of the chapters'
// bvh_traversal.glsl with the same ray-triangle test as the chapters, checked against
// brute force.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "bvh.h"
#include "obj_loader.h"
#ifdef BVH_TEST_TRAVERSAL_THREADED
#include <cstring>

#include "threaded_tree.h"
#endif

namespace bvh_test {

// A triangle mesh: positions and 3 indices per triangle, as buildBvh() takes them.
struct TestMesh {
    std::string name;
    std::vector<glm::vec3> positions;
    std::vector<uint32_t> indices;
    TestMesh(std::string name = {}, std::vector<glm::vec3> positions = {},
             std::vector<uint32_t> indices = {})
        : name(std::move(name)), positions(std::move(positions)), indices(std::move(indices)) {}
    size_t triangleCount() const { return indices.size() / 3; }
    void add(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
        uint32_t first = uint32_t(positions.size());
        positions.insert(positions.end(), {a, b, c});
        indices.insert(indices.end(), {first, first + 1, first + 2});
    }
};

// SplitMix64: the same numbers with every compiler and standard library (unlike
// std::uniform_real_distribution), so a failing case can be reproduced anywhere.
class Random {
public:
    explicit Random(uint64_t seed) : state_(seed) {}
    uint64_t next() {
        uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    }
    float uniform() { return float(next() >> 40) * (1.0f / 16777216.0f); }  // [0, 1)
    float uniform(float low, float high) { return low + (high - low) * uniform(); }
    glm::vec3 inBox(glm::vec3 low, glm::vec3 high) {
        return {uniform(low.x, high.x), uniform(low.y, high.y), uniform(low.z, high.z)};
    }
    glm::vec3 unitVector() {  // uniform on the sphere
        float z = uniform(-1.0f, 1.0f), phi = uniform(0.0f, 6.2831853f);
        float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
        return {r * std::cos(phi), r * std::sin(phi), z};
    }

private:
    uint64_t state_;
};

// n triangles of random size (up to `size`) and orientation in the unit cube.
inline TestMesh randomSoup(size_t n, uint64_t seed, float size = 0.1f) {
    TestMesh mesh{"soup_" + std::to_string(n)};
    Random random(seed);
    for (size_t i = 0; i < n; ++i) {
        glm::vec3 centre = random.inBox(glm::vec3(0.0f), glm::vec3(1.0f));
        mesh.add(centre + size * random.uniform() * random.unitVector(),
                 centre + size * random.uniform() * random.unitVector(),
                 centre + size * random.uniform() * random.unitVector());
    }
    return mesh;
}

// A flat grid of cells x cells squares (2 triangles each) in the plane y = 0: boxes of
// zero height, many equal centroid coordinates, rays that meet shared edges.
inline TestMesh flatGrid(int cells) {
    TestMesh mesh{"grid_" + std::to_string(cells)};
    for (int i = 0; i < cells; ++i)
        for (int j = 0; j < cells; ++j) {
            glm::vec3 a(i, 0, j), b(i + 1, 0, j), c(i + 1, 0, j + 1), d(i, 0, j + 1);
            mesh.add(a, b, c);
            mesh.add(a, c, d);
        }
    return mesh;
}

// n parallel triangles in the planes x = 1, 1/3, 1/9, ... With 2 bins
// (BvhOptions::binCount) the only split plane lies halfway along the centroids, which
// separates just the farthest triangle from the rest: without the depth limit the tree
// would be about n deep. A ray along +x hits the deepest one first.
inline TestMesh peelingChain(int n) {
    TestMesh mesh{"peeling_chain_" + std::to_string(n)};
    for (int i = 0; i < n; ++i) {
        float x = std::pow(3.0f, -float(i));
        mesh.add({x, 0.0f, 0.0f}, {x, 1.0f, 0.0f}, {x, 0.0f, 1.0f});
    }
    return mesh;
}

// The teapots the build generates (cmake/Assets.cmake). The big ones exist only after
// `cmake --build build --target course_benchmark_assets`; COURSE_BVH_MESH_DIR names
// another folder to look in first.
inline std::filesystem::path meshDir() {
    const char* dir = std::getenv("COURSE_BVH_MESH_DIR");
    return dir ? std::filesystem::path(dir)
               : std::filesystem::path(COURSE_GENERATED_ASSET_DIR) / "meshes";
}

// The teapot `name` (e.g. "teapot_6320"), or an empty mesh when it was not generated.
inline TestMesh loadTeapot(const std::string& name) {
    namespace fs = std::filesystem;
    fs::path path = meshDir() / (name + ".obj");
    if (!fs::exists(path))
        path = fs::path(COURSE_GENERATED_ASSET_DIR) / "meshes" / (name + ".obj");
    if (!fs::exists(path)) return {};
    Mesh mesh = loadObj(path.string());
    return {name, mesh.positions, mesh.positionIndices};
}

// --- The traversal, in C++ -----------------------------------------------------------

struct Ray {
    glm::vec3 origin, direction;
};

struct RayHit {
    bool found = false;
    uint32_t triangle = 0;  // in leaf order for the BVH, input order for brute force
    float t = 0.0f;
    glm::vec2 uv{0.0f};
};

// Moller-Trumbore exactly as the chapters' triangle.glsl writes it.
inline bool hitTriangle(const Ray& ray, glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, float tMin,
                        float tMax, float& t, glm::vec2& uv) {
    glm::vec3 edge1 = p1 - p0, edge2 = p2 - p0;
    glm::vec3 p = glm::cross(ray.direction, edge2);
    float determinant = glm::dot(edge1, p);
    if (std::abs(determinant) < 1e-12f) return false;
    float inverse = 1.0f / determinant;
    glm::vec3 toOrigin = ray.origin - p0;
    float u = glm::dot(toOrigin, p) * inverse;
    if (u < 0.0f || u > 1.0f) return false;
    glm::vec3 q = glm::cross(toOrigin, edge1);
    float v = glm::dot(ray.direction, q) * inverse;
    if (v < 0.0f || u + v > 1.0f) return false;
    t = glm::dot(edge2, q) * inverse;
    uv = {u, v};
    return t > tMin && t < tMax;
}

inline bool hitMeshTriangle(const TestMesh& mesh, uint32_t triangle, const Ray& ray,
                            float tMin, float tMax, float& t, glm::vec2& uv) {
    const uint32_t* corner = &mesh.indices[3 * size_t(triangle)];
    return hitTriangle(ray, mesh.positions[corner[0]], mesh.positions[corner[1]],
                       mesh.positions[corner[2]], tMin, tMax, t, uv);
}

// Every triangle, in input order: the answer the BVH must give.
inline RayHit bruteForce(const TestMesh& mesh, const Ray& ray, float tMin, float tMax,
                         bool anyHit) {
    RayHit hit;
    hit.t = tMax;
    for (uint32_t i = 0; i < mesh.triangleCount(); ++i) {
        float t;
        glm::vec2 uv;
        if (hitMeshTriangle(mesh, i, ray, tMin, hit.t, t, uv)) {
            hit = {true, i, t, uv};
            if (anyHit) break;
        }
    }
    return hit;
}

constexpr float kMiss = 3.0e38f;

// bvh_traversal.glsl's bvhRay() and bvhEnterBox(), line by line.
struct BoxRay {
    glm::vec3 origin, inverseDirection;
    glm::bvec3 negative;
    explicit BoxRay(const Ray& ray) : origin(ray.origin) {
        const float tiny = 1e-30f;
        for (int a = 0; a < 3; ++a) {
            float d = std::abs(ray.direction[a]) < tiny ? tiny : ray.direction[a];
            inverseDirection[a] = 1.0f / d;
            negative[a] = inverseDirection[a] < 0.0f;
        }
    }
    float enter(glm::vec3 boxMin, glm::vec3 boxMax, float tMin, float tMax) const {
        glm::vec3 tNear, tFar;
        for (int a = 0; a < 3; ++a) {
            float nearPlane = negative[a] ? boxMax[a] : boxMin[a];
            float farPlane = negative[a] ? boxMin[a] : boxMax[a];
            tNear[a] = (nearPlane - origin[a]) * inverseDirection[a];
            tFar[a] = (farPlane - origin[a]) * inverseDirection[a];
        }
        float enter = std::max(std::max(tNear.x, tNear.y), std::max(tNear.z, tMin));
        float exit = std::min(std::min(tFar.x, tFar.y), std::min(tFar.z, tMax));
        return enter <= exit * 1.0000004f ? enter : kMiss;
    }
};

struct TraversalCount {
    int loopIterations = 0;  // what bvhLoopIterations counts
    // Turns of all the traversal's loops, a while loop's last check that ends it too:
    // what a GL's loop limit counts (Mesa 22's llvmpipe, measured in test_bvh_gpu).
    int loopTurns = 0;
    int nodeFetches = 0;
    int triangleTests = 0;
    int maxStack = 0;
};

// The three traversals the course writes, each a line-by-line port of one
// bvh_traversal.glsl. They visit the same boxes in different orders; each must find
// exactly what brute force finds in any valid tree. `mesh` is in leaf order (reordered()).
// The chapter's own is `traverse`, chosen below.
namespace ports {

// Tests a leaf's triangles, as bvhTestTriangle() written out: a nearer hit replaces the
// nearest so far.
inline void testLeaf(const TestMesh& mesh, const Ray& ray, uint32_t first, uint32_t count,
                     float tMin, RayHit& hit, TraversalCount& counted) {
    for (uint32_t i = 0; i < count && i < BVH_MAX_LEAF_SIZE; ++i) {
        ++counted.triangleTests;
        float t;
        glm::vec2 uv;
        if (hitMeshTriangle(mesh, first + i, ray, tMin, hit.t, t, uv))
            hit = {true, first + i, t, uv};
    }
}

// shaders/13_bvh/bvh_traversal.glsl: one loop; the left child goes on, the right one is
// put aside, and a child taken back is visited whatever the hits found since.
inline RayHit leftFirst(const Bvh& bvh, const TestMesh& mesh, const Ray& ray, float tMin,
                        float tMax, bool anyHit, TraversalCount* count = nullptr) {
    TraversalCount local;
    TraversalCount& counted = count ? *count : local;
    BoxRay boxRay(ray);
    RayHit hit;
    hit.t = std::min(tMax, 1.0e38f);
    glm::uvec2 current(0u, 0u);
    bool haveCurrent = true;
    glm::uvec2 stack[BVH_MAX_DEPTH];
    int stackSize = 0;
    for (;;) {
        ++counted.loopIterations;
        ++counted.loopTurns;
        if (!haveCurrent) {
            if (stackSize == 0) break;
            current = stack[--stackSize];
        }
        haveCurrent = false;
        const uint32_t first = current.x, triangles = current.y;
        if (triangles > 0) {
            testLeaf(mesh, ray, first, triangles, tMin, hit, counted);
            if (hit.found && anyHit) return hit;
            continue;
        }
        const gpu::BvhNode& node = bvh.nodes.at(first);
        ++counted.nodeFetches;
        float enterLeft = boxRay.enter(node.leftMin, node.leftMax, tMin, hit.t);
        float enterRight = boxRay.enter(node.rightMin, node.rightMax, tMin, hit.t);
        if (enterLeft < hit.t) {
            current = {node.leftIndex, node.leftCount};
            haveCurrent = true;
        }
        if (enterRight < hit.t && stackSize < BVH_MAX_DEPTH) {
            stack[stackSize++] = {node.rightIndex, node.rightCount};
            counted.maxStack = std::max(counted.maxStack, stackSize);
        }
    }
    return hit;
}

// shaders/14_bvh_sah/bvh_traversal.glsl (to 18): one loop; the child the ray enters
// first goes on, and a child taken back is skipped if the ray enters it behind a hit.
inline RayHit nearFirst(const Bvh& bvh, const TestMesh& mesh, const Ray& ray, float tMin,
                        float tMax, bool anyHit, TraversalCount* count = nullptr) {
    TraversalCount local;
    TraversalCount& counted = count ? *count : local;
    BoxRay boxRay(ray);
    RayHit hit;
    hit.t = std::min(tMax, 1.0e38f);
    glm::uvec2 current(0u, 0u);
    bool haveCurrent = true;
    glm::uvec2 stack[BVH_MAX_DEPTH];
    float stackEnter[BVH_MAX_DEPTH];
    int stackSize = 0;
    for (;;) {
        ++counted.loopIterations;
        ++counted.loopTurns;
        if (!haveCurrent) {
            if (stackSize == 0) break;
            --stackSize;
            if (stackEnter[stackSize] >= hit.t) continue;
            current = stack[stackSize];
        }
        haveCurrent = false;
        const uint32_t first = current.x, triangles = current.y;
        if (triangles > 0) {
            testLeaf(mesh, ray, first, triangles, tMin, hit, counted);
            if (hit.found && anyHit) return hit;
            continue;
        }
        const gpu::BvhNode& node = bvh.nodes.at(first);
        ++counted.nodeFetches;
        float enterLeft = boxRay.enter(node.leftMin, node.leftMax, tMin, hit.t);
        float enterRight = boxRay.enter(node.rightMin, node.rightMax, tMin, hit.t);
        glm::uvec2 left(node.leftIndex, node.leftCount);
        glm::uvec2 right(node.rightIndex, node.rightCount);
        bool leftFirst = enterLeft <= enterRight;
        glm::uvec2 nearChild = leftFirst ? left : right, farChild = leftFirst ? right : left;
        float enterNear = std::min(enterLeft, enterRight);
        float enterFar = std::max(enterLeft, enterRight);
        if (enterNear < hit.t) {
            current = nearChild;
            haveCurrent = true;
        }
        if (enterFar < hit.t && stackSize < BVH_MAX_DEPTH) {
            stack[stackSize] = farChild;
            stackEnter[stackSize] = enterFar;
            ++stackSize;
            counted.maxStack = std::max(counted.maxStack, stackSize);
        }
    }
    return hit;
}

// shaders/21_tree_price/bvh_traversal.glsl (and 22, 23): the same visits as nearFirst, in three
// loops ("while-while": down node after node, one leaf, then off the stack), and a
// stack entry one uint, the index above the count's BVH_COUNT_BITS.
inline RayHit whileWhile(const Bvh& bvh, const TestMesh& mesh, const Ray& ray, float tMin,
                         float tMax, bool anyHit, TraversalCount* count = nullptr) {
#ifdef BVH_COUNT_BITS
    constexpr uint32_t countBits = BVH_COUNT_BITS;
#else
    constexpr uint32_t countBits = 3u;  // a layout without packing: the same 3 bits
#endif
    auto pack = [](glm::uvec2 child) { return (child.x << countBits) | child.y; };
    auto unpack = [](uint32_t entry) {
        return glm::uvec2(entry >> countBits, entry & ((1u << countBits) - 1u));
    };
    TraversalCount local;
    TraversalCount& counted = count ? *count : local;
    BoxRay boxRay(ray);
    RayHit hit;
    hit.t = std::min(tMax, 1.0e38f);
    glm::uvec2 current(0u, 0u);
    bool haveCurrent = true;
    uint32_t stack[BVH_MAX_DEPTH];
    float stackEnter[BVH_MAX_DEPTH];
    int stackSize = 0;
    // loopTurns counts each while loop's condition checks, the last one that ends it
    // too: a GL runs that as one more turn, which checks and leaves.
    for (;;) {
        ++counted.loopTurns;
        while (++counted.loopTurns, haveCurrent && current.y == 0u) {  // 1. down the tree
            ++counted.loopIterations;
            const gpu::BvhNode& node = bvh.nodes.at(current.x);
            ++counted.nodeFetches;
            float enterLeft = boxRay.enter(node.leftMin, node.leftMax, tMin, hit.t);
            float enterRight = boxRay.enter(node.rightMin, node.rightMax, tMin, hit.t);
            glm::uvec2 left(node.leftIndex, node.leftCount);
            glm::uvec2 right(node.rightIndex, node.rightCount);
            bool leftFirst = enterLeft <= enterRight;
            glm::uvec2 nearChild = leftFirst ? left : right;
            glm::uvec2 farChild = leftFirst ? right : left;
            float enterNear = std::min(enterLeft, enterRight);
            float enterFar = std::max(enterLeft, enterRight);
            haveCurrent = enterNear < hit.t;
            if (haveCurrent) current = nearChild;
            if (enterFar < hit.t && stackSize < BVH_MAX_DEPTH) {
                stack[stackSize] = pack(farChild);
                stackEnter[stackSize] = enterFar;
                ++stackSize;
                counted.maxStack = std::max(counted.maxStack, stackSize);
            }
        }
        if (haveCurrent) {  // 2. a leaf
            ++counted.loopIterations;
            testLeaf(mesh, ray, current.x, current.y, tMin, hit, counted);
            if (hit.found && anyHit) return hit;
        }
        haveCurrent = false;  // 3. off the stack
        while (++counted.loopTurns, stackSize > 0 && !haveCurrent) {
            --stackSize;
            haveCurrent = stackEnter[stackSize] < hit.t;
            current = unpack(stack[stackSize]);
        }
        if (!haveCurrent) break;
    }
    return hit;
}

#ifdef BVH_TEST_TRAVERSAL_THREADED
// The boxes threadTree() lays out for `bvh`, made once for each tree the tests walk
// (the ports take the tree; a walk of thousands of rays would lay them out each time).
inline const std::vector<gpu::BvhBox>& threadedBoxes(const Bvh& bvh) {
    static std::vector<gpu::BvhNode> nodes;
    static std::vector<gpu::BvhBox> boxes;
    const size_t bytes = bvh.nodes.size() * sizeof(gpu::BvhNode);
    if (nodes.size() != bvh.nodes.size() || boxes.empty() ||
        std::memcmp(nodes.data(), bvh.nodes.data(), bytes) != 0) {
        nodes = bvh.nodes;
        boxes = threadTree(bvh);
    }
    return boxes;
}

// shaders/31_stackless_tree/bvh_traversal.glsl: no stack; the boxes of threadTree() in
// the order of the ray's octant, one a turn, each box's planes near corner first, on the
// grid; a box missed sends the walk past its subtree; while-while, as chapter 21.
inline RayHit threaded(const Bvh& bvh, const TestMesh& mesh, const Ray& ray, float tMin,
                       float tMax, bool anyHit, TraversalCount* count = nullptr) {
    const std::vector<gpu::BvhBox>& boxes = threadedBoxes(bvh);
    TraversalCount local;
    TraversalCount& counted = count ? *count : local;
    gpu::BvhGrid grid;
    std::memcpy(&grid, boxes.data(), sizeof(grid));
    const BoxRay boxRay(ray);
    const glm::vec3 origin = (boxRay.origin - grid.origin) / grid.step;
    const glm::vec3 inverse = boxRay.inverseDirection * grid.step;
    RayHit hit;
    hit.t = std::min(tMax, 1.0e38f);
    const uint32_t mask = (1u << BVH_COUNT_BITS) - 1u;
    uint32_t octant = (boxRay.negative.x ? 1u : 0u) | (boxRay.negative.y ? 2u : 0u) |
                      (boxRay.negative.z ? 4u : 0u);
    uint32_t next = octant * grid.boxesPerOrder, end = next + grid.boxesPerOrder;
    for (;;) {
        ++counted.loopTurns;
        uint32_t leaf = 0u;
        while (++counted.loopTurns, next != end) {  // 1. box after box
            ++counted.loopIterations;
            ++counted.nodeFetches;
            const gpu::BvhBox& box = boxes.at(BVH_GRID_BOXES + next);
            glm::vec3 nearCorner(box.nearXY & 0xFFFFu, box.nearXY >> 16u,
                                 box.nearZFarX & 0xFFFFu);
            glm::vec3 farCorner(box.nearZFarX >> 16u, box.farYZ & 0xFFFFu, box.farYZ >> 16u);
            glm::vec3 tNear = (nearCorner - origin) * inverse;
            glm::vec3 tFar = (farCorner - origin) * inverse;
            float enter = std::max(std::max(tNear.x, tNear.y), std::max(tNear.z, tMin));
            float exit = std::min(std::min(tFar.x, tFar.y), std::min(tFar.z, hit.t));
            bool enters = (enter <= exit * 1.0000004f ? enter : kMiss) < hit.t;
            bool isLeaf = (box.next & mask) != 0u;
            next = enters || isLeaf ? next + 1u : box.next >> BVH_COUNT_BITS;
            if (enters && isLeaf) {
                leaf = box.next;
                break;
            }
        }
        if (leaf == 0u) break;
        ++counted.loopIterations;  // 2. a leaf
        testLeaf(mesh, ray, leaf >> BVH_COUNT_BITS, leaf & mask, tMin, hit, counted);
        if (hit.found && anyHit) return hit;
    }
    return hit;
}
#endif

}  // namespace ports

// The chapter's traversal: bvh_tests.cmake reads which one its bvh_traversal.glsl is.
inline RayHit traverse(const Bvh& bvh, const TestMesh& mesh, const Ray& ray, float tMin,
                       float tMax, bool anyHit, TraversalCount* count = nullptr) {
#if defined(BVH_TEST_TRAVERSAL_LEFT_FIRST)
    return ports::leftFirst(bvh, mesh, ray, tMin, tMax, anyHit, count);
#elif defined(BVH_TEST_TRAVERSAL_WHILE_WHILE)
    return ports::whileWhile(bvh, mesh, ray, tMin, tMax, anyHit, count);
#elif defined(BVH_TEST_TRAVERSAL_NEAR_FIRST)
    return ports::nearFirst(bvh, mesh, ray, tMin, tMax, anyHit, count);
#elif defined(BVH_TEST_TRAVERSAL_THREADED)
    return ports::threaded(bvh, mesh, ray, tMin, tMax, anyHit, count);
#else
#error "bvh_tests.cmake names the chapter's traversal: BVH_TEST_TRAVERSAL_NEAR_FIRST etc."
#endif
}

// The mesh with its triangles in the BVH's leaf order (what the chapter uploads).
inline TestMesh reordered(const TestMesh& mesh, const Bvh& bvh) {
    TestMesh leafOrder{mesh.name, mesh.positions, {}};
    leafOrder.indices.reserve(mesh.indices.size());
    for (uint32_t input : bvh.triangleOrder)
        for (int k = 0; k < 3; ++k) leafOrder.indices.push_back(mesh.indices[3 * input + k]);
    return leafOrder;
}

// --- Rays ----------------------------------------------------------------------------

struct Bounds {
    glm::vec3 min{std::numeric_limits<float>::max()}, max{-std::numeric_limits<float>::max()};
};
inline Bounds boundsOf(const TestMesh& mesh) {
    Bounds bounds;
    for (const glm::vec3& p : mesh.positions) {
        bounds.min = glm::min(bounds.min, p);
        bounds.max = glm::max(bounds.max, p);
    }
    return bounds;
}

// A mix of the rays a renderer shoots: from outside towards points of the mesh's box
// (camera rays), from inside in random directions (bounces), along the axes (zero
// direction components), and from points on triangles (shadow rays and bounces).
inline std::vector<Ray> testRays(const TestMesh& mesh, size_t n, uint64_t seed) {
    Random random(seed);
    Bounds bounds = boundsOf(mesh);
    glm::vec3 centre = 0.5f * (bounds.min + bounds.max);
    float radius = std::max(1e-3f, glm::length(bounds.max - bounds.min));
    std::vector<Ray> rays;
    for (size_t i = 0; i < n; ++i) {
        glm::vec3 target = random.inBox(bounds.min, bounds.max);
        switch (i % 4) {
        case 0: {  // from a sphere around the mesh towards a point in its box
            glm::vec3 origin = centre + 1.5f * radius * random.unitVector();
            rays.push_back({origin, glm::normalize(target - origin)});
            break;
        }
        case 1:  // from inside the box, any direction
            rays.push_back({random.inBox(bounds.min, bounds.max), random.unitVector()});
            break;
        case 2: {  // along an axis
            glm::vec3 direction(0.0f);
            direction[random.next() % 3] = (random.next() & 1) ? 1.0f : -1.0f;
            rays.push_back({target - radius * direction, direction});
            break;
        }
        default: {  // from a point on a triangle, any direction
            if (mesh.triangleCount() == 0) {
                rays.push_back({target, random.unitVector()});
                break;
            }
            uint32_t triangle = uint32_t(random.next() % mesh.triangleCount());
            float u = random.uniform(), v = random.uniform();
            if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
            const uint32_t* corner = &mesh.indices[3 * size_t(triangle)];
            glm::vec3 p0 = mesh.positions[corner[0]], p1 = mesh.positions[corner[1]],
                      p2 = mesh.positions[corner[2]];
            rays.push_back({p0 + u * (p1 - p0) + v * (p2 - p0), random.unitVector()});
            break;
        }
        }
    }
    return rays;
}

}  // namespace bvh_test
