// A chapter's bvh_traversal.glsl on the GPU (headless llvmpipe here), built once per
// distinct tree (bvh_tests.cmake): it compiles, and for thousands of rays against trees
// from the chapter's buildBvh() it finds the same hits as the C++ port of it in
// bvh_test_support.h, which test_bvh checks against brute force. Also measures the
// traversal's loop iterations per ray: Mesa 22's llvmpipe ends an invocation after 65535
// in all, silently (common/course/loop_budget.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <numeric>

#include "bvh_tree_checks.h"
#include "course/gl_context.h"
#include "course/gpu_buffer.h"
#include "course/loop_budget.h"
#include "course/shader_program.h"
#include "course/shader_source.h"

using namespace bvh_test;

namespace {

// The structs of tests/data/bvh/traversal_test.comp, std430.
struct RayQuery {
    glm::vec4 origin, direction;
    glm::vec4 limits;  // tMin, tMax (nearest), tMax (any)
};
struct RayResult {
    uint32_t found, triangle;
    float t;
    uint32_t anyFound;
    glm::vec2 uv;
    uint32_t iterations, anyIterations;
};
static_assert(sizeof(RayQuery) == 48 && sizeof(RayResult) == 32, "std430");
static_assert(offsetof(RayResult, uv) == 16 && offsetof(RayResult, iterations) == 24, "std430");

// llvmpipe runs 8 invocations in lockstep (256-bit vectors of 32-bit lanes), and Mesa
// 22's loop limit counts the iterations of the group: the slowest of the 8 decides.
constexpr size_t kLockstep = 8;
// The traversal must stay far below the smallest limit a GL is known to have.
constexpr uint32_t kSmallestKnownLoopLimit = uint32_t(course::kSmallestKnownLoopLimit);

struct Summary {
    size_t rays = 0, hits = 0, ties = 0, mismatches = 0;
    double meanIterations = 0.0;
    uint32_t maxIterations = 0;    // one ray, nearest-hit query
    uint32_t maxAnyIterations = 0; // one ray, any-hit query
    uint32_t maxLockstep = 0;      // the slowest of 8 neighbours, both queries
    // The C++ port's count of every loop's turns, which a GL's loop limit counts
    // (TraversalCount::loopTurns: more than bvhLoopIterations from chapter 21 on).
    uint32_t maxLockstepTurns = 0;
    size_t countMismatches = 0;    // rays where the GPU and the port iterate differently
};

class BvhGpuTest : public ::testing::Test {
protected:
    void SetUp() override {
        course::Options options;
        options.backend = course::Backend::Egl;
        context = course::createGlContext(options, {4, 3}, "test");
    }

    course::ShaderProgram program() {
        // The test shader lives with the test data; its includes are the chapter's.
        return course::ShaderProgram::compute(BVH_TEST_SHADER_DIR,
                                              "../../tests/data/bvh/traversal_test.comp",
                                              traversalAsTheTestCallsIt());
    }

    // The test shader gives the traversal a storage buffer of nodes at binding 0, which
    // chapters 13 to 19's traversal declares itself. From chapter 20 on the includer
    // reads the nodes (bvhNodeAt(), scene_memory.glsl, from a buffer texture or a
    // storage buffer): for those, the traversal is included with a storage buffer's
    // bvhNodeAt() before it, the chapter's file unchanged. Chapter 26's walk also goes
    // down instances' trees and answers with a BvhHit: it is included with a world of
    // no instances before it and the test shader's form of bvhNearestHit() after it,
    // so these checks cover its walk of the world's own tree (the instances' part is
    // test_26_instances.py's, against the same triangles written out). Chapter 31's walk
    // reads threaded boxes and their grid (bvhBoxAt(), bvhGrid()): those come from a
    // storage buffer of threadTree()'s boxes in the nodes' place.
    static course::GeneratedFiles traversalAsTheTestCallsIt() {
        const std::string path = BVH_TEST_SHADER_DIR "/bvh_traversal.glsl";
        std::optional<std::string> traversal = course::readShaderFile(path);
        if (!traversal) ADD_FAILURE() << "cannot read " << path;
        if (!traversal) return {};
        if (traversal->find("bvhBoxAt(") != std::string::npos)  // chapter 31
            return {{"bvh_traversal.glsl",
                     "layout(std430, binding = BVH_NODES_BINDING) readonly buffer BvhBoxes {\n"
                     "    BvhBox bvhBoxes[];\n"
                     "};\n"
                     "BvhBox bvhBoxAt(uint i) { return bvhBoxes[BVH_GRID_BOXES + i]; }\n"
                     "BvhGrid bvhGrid() {\n"
                     "    BvhBox a = bvhBoxes[0], b = bvhBoxes[1];\n"
                     "    return BvhGrid(uintBitsToFloat(uvec3(a.nearXY, a.nearZFarX, a.farYZ)),\n"
                     "                   a.next, uintBitsToFloat(uvec3(b.nearXY, b.nearZFarX,\n"
                     "                   b.farYZ)), 0u);\n"
                     "}\n" +
                         *traversal}};
        if (traversal->find("bvhNodeAt(") != std::string::npos)
            return {{"bvh_traversal.glsl",
                     "layout(std430, binding = BVH_NODES_BINDING) readonly buffer BvhNodes {\n"
                     "    BvhNode bvhNodes[];\n"
                     "};\n"
                     "BvhNode bvhNodeAt(uint i) { return bvhNodes[i]; }\n" +
                         *traversal}};
        if (traversal->find("struct BvhHit") != std::string::npos)
            return {{"bvh_traversal.glsl", std::string(kNoInstances) + *traversal +
                                               kNearestHitAsBefore}};
        return {};
    }

    // What chapter 26's traversal needs of instances.glsl and the path parameters, for a
    // world without instances.
    static constexpr const char* kNoInstances = R"(
#define NO_SPHERE 0xFFFFFFFFu
#define NO_INSTANCE 0xFFFFFFFFu
struct Instance {
    vec4 objectFromWorld0, objectFromWorld1, objectFromWorld2;
    uint root, firstSphere, sphereCount, unused;
};
const uint instanceCount = 0u;
const uint instanceRoot = 0u;
Instance instanceAt(uint index) { return Instance(vec4(0.0), vec4(0.0), vec4(0.0), 0u, 0u, 0u, 0u); }
Ray rayToObject(Ray ray, Instance placed) { return ray; }
bool hitObjectSphere(Ray ray, uint sphere, float tMin, float tMax, out float t) {
    t = tMax;
    return false;
}
)";
    // The earlier chapters' bvhNearestHit(), which the test shader calls.
    static constexpr const char* kNearestHitAsBefore = R"(
bool bvhNearestHit(Ray ray, float tMin, float tMax, out uint triangle, out float t,
                   out vec2 uv) {
    BvhHit hit;
    bool found = bvhNearestHit(ray, tMin, tMax, hit);
    triangle = hit.triangle;
    t = hit.t;
    uv = hit.uv;
    return found;
}
)";

    // Runs the rays on the GPU, `repeats` times each; returns the results.
    std::vector<RayResult> runOnGpu(const Bvh& bvh, const TestMesh& leafOrder,
                                    const std::vector<RayQuery>& queries,
                                    uint32_t repeats = 1,
                                    std::vector<uint32_t>* completed = nullptr) {
        std::vector<glm::vec4> positions;
        for (const glm::vec3& p : leafOrder.positions) positions.emplace_back(p, 1.0f);
        if (positions.empty()) positions.emplace_back(0.0f);  // no empty buffers
        std::vector<glm::uvec4> triangles;
        for (size_t i = 0; i < leafOrder.triangleCount(); ++i)
            triangles.emplace_back(leafOrder.indices[3 * i], leafOrder.indices[3 * i + 1],
                                   leafOrder.indices[3 * i + 2], 0u);
        if (triangles.empty()) triangles.emplace_back(0u);
#ifdef BVH_TEST_TRAVERSAL_THREADED
        auto nodeBuffer = course::GpuBuffer::fromVector(ports::threadedBoxes(bvh));
#else
        auto nodeBuffer = course::GpuBuffer::fromVector(bvh.nodes);
#endif
        auto positionBuffer = course::GpuBuffer::fromVector(positions);
        auto triangleBuffer = course::GpuBuffer::fromVector(triangles);
        auto queryBuffer = course::GpuBuffer::fromVector(queries);
        course::GpuBuffer resultBuffer(queries.size() * sizeof(RayResult));
        course::GpuBuffer completedBuffer(queries.size() * sizeof(uint32_t));
        nodeBuffer.bindStorage(0);
        positionBuffer.bindStorage(1);
        triangleBuffer.bindStorage(2);
        queryBuffer.bindStorage(3);
        resultBuffer.bindStorage(4);
        completedBuffer.bindStorage(5);
        course::ShaderProgram& shader = compiled();
        shader.use();
        shader.set("repeats", repeats);
        shader.dispatchCovering(int(queries.size()));
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        if (completed) *completed = completedBuffer.readAll<uint32_t>();
        return resultBuffer.readAll<RayResult>();
    }

    course::ShaderProgram& compiled() {
        if (!shader_.id()) shader_ = program();
        return shader_;
    }

    // The rays of testRays(), their limits, the GPU's answers and the C++ traversal's;
    // returns what agreed and how many loop iterations it took.
    Summary compare(const TestMesh& mesh, size_t rayCount, uint64_t seed,
                    const TreeOptions& options = {}) {
        SCOPED_TRACE(mesh.name);
        Bvh bvh = buildTree(mesh, options);
        TestMesh leafOrder = reordered(mesh, bvh);
        Bounds bounds = boundsOf(mesh);
        const float scale = std::max(1.0f, glm::length(bounds.max - bounds.min));
        const float tMin = 1e-5f * scale;
        std::vector<Ray> rays = testRays(mesh, rayCount, seed);
        std::vector<RayQuery> queries;
        std::vector<RayHit> expected;
        std::vector<TraversalCount> counts(rays.size()), anyCounts(rays.size());
        for (size_t i = 0; i < rays.size(); ++i) {
            const Ray& ray = rays[i];
            RayHit hit = traverse(bvh, leafOrder, ray, tMin, 1e30f, false, &counts[i]);
            expected.push_back(hit);
            // Any hit: half the rays ask "anything before the nearest hit?" (a shadow ray
            // to a point just short of it: no), the others "anything at all?".
            float anyTMax = (i % 2 == 0 && hit.found) ? 0.999f * hit.t : 1e30f;
            queries.push_back({glm::vec4(ray.origin, 0.0f), glm::vec4(ray.direction, 0.0f),
                               glm::vec4(tMin, 1e30f, anyTMax, 0.0f)});
        }
        std::vector<RayResult> results = runOnGpu(bvh, leafOrder, queries);

        Summary summary;
        summary.rays = rays.size();
        for (size_t i = 0; i < rays.size(); ++i) {
            const RayResult& got = results[i];
            const RayHit& want = expected[i];
            const RayQuery& query = queries[i];
            bool wantAny =
                traverse(bvh, leafOrder, rays[i], tMin, query.limits.z, true, &anyCounts[i])
                    .found;
            // The same loop iterations: the port is this chapter's traversal.
            if (got.iterations != uint32_t(counts[i].loopIterations) ||
                got.anyIterations != uint32_t(anyCounts[i].loopIterations))
                ++summary.countMismatches;
            bool agree = bool(got.found) == want.found && bool(got.anyFound) == wantAny;
            if (agree && want.found) {
                ++summary.hits;
                float tolerance = 1e-5f * std::max(1.0f, want.t);
                agree = std::abs(got.t - want.t) <= tolerance &&
                        got.triangle < mesh.triangleCount();
                if (agree && got.triangle != want.triangle) {
                    // A tie: the GPU's triangle is hit at the same distance (shared edge).
                    float t;
                    glm::vec2 uv;
                    agree =
                        hitMeshTriangle(leafOrder, got.triangle, rays[i], tMin, 1e30f, t, uv) &&
                        std::abs(t - want.t) <= tolerance;
                    ++summary.ties;
                }
            }
            if (!agree) {
                ++summary.mismatches;
                if (summary.mismatches <= 5)
                    std::cout << "mismatch: ray " << i << ": GPU found " << got.found
                              << " triangle " << got.triangle << " t " << got.t << " any "
                              << got.anyFound << "; C++ found " << want.found << " triangle "
                              << want.triangle << " t " << want.t << " any " << wantAny
                              << "\n";
            }
            summary.meanIterations += got.iterations;
            summary.maxIterations = std::max(summary.maxIterations, got.iterations);
            summary.maxAnyIterations = std::max(summary.maxAnyIterations, got.anyIterations);
        }
        summary.meanIterations /= double(std::max<size_t>(1, rays.size()));
        // The slowest of each 8 neighbours, as the group runs its two loops in lockstep.
        for (size_t group = 0; group < rays.size(); group += kLockstep) {
            uint32_t nearest = 0, any = 0, nearestTurns = 0, anyTurns = 0;
            for (size_t i = group; i < std::min(rays.size(), group + kLockstep); ++i) {
                nearest = std::max(nearest, results[i].iterations);
                any = std::max(any, results[i].anyIterations);
                nearestTurns = std::max(nearestTurns, uint32_t(counts[i].loopTurns));
                anyTurns = std::max(anyTurns, uint32_t(anyCounts[i].loopTurns));
            }
            summary.maxLockstep = std::max(summary.maxLockstep, nearest + any);
            summary.maxLockstepTurns =
                std::max(summary.maxLockstepTurns, nearestTurns + anyTurns);
        }
        // llvmpipe and the CPU agree on every ray. Another GPU may round differently
        // (fused multiply-adds) and see a ray that grazes an edge otherwise: a few.
        EXPECT_LE(summary.mismatches, summary.rays / 2000) << mesh.name;
        EXPECT_LE(summary.countMismatches, summary.rays / 2000) << mesh.name;
        std::cout << mesh.name << " (" << mesh.triangleCount() << " triangles, depth "
                  << deepestLeaf(bvh) << "): " << summary.rays << " rays, "
                  << summary.hits << " hits, " << summary.ties << " ties, "
                  << summary.mismatches << " mismatches (" << summary.countMismatches
                  << " in loop iterations); loop iterations per ray: nearest "
                  << summary.meanIterations << " mean, " << summary.maxIterations
                  << " max; any " << summary.maxAnyIterations << " max; lockstep group of "
                  << kLockstep << " both queries " << summary.maxLockstep << " max, "
                  << summary.maxLockstepTurns << " loop turns\n";
        return summary;
    }

    std::unique_ptr<course::GlContext> context;
    course::ShaderProgram shader_;
};

}  // namespace

TEST_F(BvhGpuTest, TraversalShaderCompiles) {
    course::ShaderProgram shader = program();
    EXPECT_NE(shader.id(), 0u);
    EXPECT_EQ(shader.workGroupSize().x, 64);
}

TEST_F(BvhGpuTest, GpuFindsWhatTheCppTraversalFinds) {
    std::vector<TestMesh> meshes = {randomSoup(2000, 21), flatGrid(24)};
    TestMesh one{"one_triangle"};
    one.add({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    meshes.push_back(one);
    meshes.push_back(TestMesh{"empty"});
    for (const char* name : {"teapot_552", "teapot_6320"}) {
        TestMesh teapot = loadTeapot(name);
        EXPECT_FALSE(teapot.positions.empty()) << name << ".obj: build course_assets";
        if (!teapot.positions.empty()) meshes.push_back(teapot);
    }
    for (const TestMesh& mesh : meshes) {
        Summary summary = compare(mesh, 8192, 99);
        EXPECT_LT(summary.maxLockstepTurns, kSmallestKnownLoopLimit / 20) << mesh.name;
    }
}

// A tree at the depth limit: the longest stack, many pops. (Only an SAH builder can be
// made to go that deep; chapter 13's halves every range.)
#ifdef BVH_TEST_OPTIONS
TEST_F(BvhGpuTest, DeepTreesTraverseCorrectly) {
    TestMesh chain = peelingChain(80);
    TreeOptions twoBins;  // the SAH alone would make it 79 deep
    twoBins.binCount = 2;
    ASSERT_EQ(buildTree(chain, twoBins).stats.maxDepth, BVH_MAX_DEPTH);
    Summary summary = compare(chain, 4096, 5, twoBins);
    EXPECT_GT(summary.hits, 1000u);
}
#endif

// A leaf's triangles are tested one after the other, written out, not in a loop, so a
// GL's loop limit counts only the traversal loop's iterations. Rays that enter every
// leaf of 2000 stacked copies of one triangle but miss them all test every triangle;
// repeat them until the traversal loops come close to the limit the GL measures (with
// the triangle tests it would be far beyond) and check that every repetition ran to the
// end; repeat them past it and check that they were cut short. Where no limit is
// measured (Mesa 25's llvmpipe, a GPU), Mesa 22's stands in, and both runs must finish.
TEST_F(BvhGpuTest, OnlyTheTraversalLoopCountsTowardsTheLimit) {
    const course::LoopLimit limit = course::measureLoopLimit(GL_COMPUTE_SHADER);
    std::cout << "loop limit: " << limit.text() << " on " << limit.driver << "\n";
    const uint32_t budget =
        limit.limited ? uint32_t(limit.iterations) : kSmallestKnownLoopLimit;
    TestMesh mesh{"stacked"};
    for (int i = 0; i < 2000; ++i) mesh.add({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    Bvh bvh = buildTree(mesh);
    TestMesh leafOrder = reordered(mesh, bvh);
    // Through the box [0,1]^2 x {0}, beside the triangle's long edge: a miss, everywhere.
    Ray ray{{0.9f, 0.9f, -1.0f}, {0.0f, 0.0f, 1.0f}};
    TraversalCount nearest, any;
    EXPECT_FALSE(traverse(bvh, leafOrder, ray, 1e-5f, 1e30f, false, &nearest).found);
    traverse(bvh, leafOrder, ray, 1e-5f, 1e30f, true, &any);
    EXPECT_EQ(nearest.triangleTests, 2000);
    // What the GL counts: every turn of every loop, the repeat loop's too. (Chapter 21's
    // traversal has three loops where the others have one; bvhLoopIterations counts
    // nodes and leaves.)
    const int iterations = nearest.loopTurns + any.loopTurns + 1;
    const int triangleTests = nearest.triangleTests + any.triangleTests;
    const uint32_t repeats = uint32_t(0.9 * budget / iterations);
    // Counted too, the triangle tests would take the loops well past the limit. (Half
    // as far again: chapter 21's three loops turn about as often as it tests triangles.)
    ASSERT_GT(uint64_t(repeats) * (iterations + triangleTests), 3 * uint64_t(budget) / 2)
        << "the triangle tests would not push past the limit: the test proves nothing";
    // One group of invocations that llvmpipe runs in lockstep.
    std::vector<RayQuery> queries(kLockstep, {glm::vec4(ray.origin, 0.0f),
                                              glm::vec4(ray.direction, 0.0f),
                                              glm::vec4(1e-5f, 1e30f, 1e30f, 0.0f)});
    std::vector<uint32_t> completed;
    std::vector<RayResult> results = runOnGpu(bvh, leafOrder, queries, repeats, &completed);
    for (size_t i = 0; i < queries.size(); ++i) {
        EXPECT_EQ(completed[i], repeats) << "invocation " << i << ": cut off";
        EXPECT_EQ(results[i].iterations, uint32_t(nearest.loopIterations));
    }
    std::cout << repeats << " repetitions of " << iterations << " loop iterations and "
              << triangleTests << " triangle tests each ran to the end: "
              << repeats * iterations << " loop iterations counted, "
              << repeats * (iterations + triangleTests) << " if triangle tests counted\n";
    // And past the limit: a GL that has one cuts the loops short (the test can see it);
    // one without runs them all.
    const uint32_t tooMany = uint32_t(1.2 * budget / iterations);
    runOnGpu(bvh, leafOrder, queries, tooMany, &completed);
    if (limit.limited)
        EXPECT_LT(completed[0], tooMany) << "the measured limit did not cut the loops short";
    else
        EXPECT_EQ(completed[0], tooMany) << "no limit was measured, but the loops were cut";
}

// The big teapots, when they are there (course_benchmark_assets or COURSE_BVH_MESH_DIR):
// for the first tree of each kind of builder only, chapter 13's and 14's
// (bvh_tests.cmake). The slowest group of eight must stay far from the smallest known
// loop limit, at a twentieth of it; the count is printed for the pages.
#ifdef BVH_TEST_BIG_TEAPOTS
TEST_F(BvhGpuTest, BigTeapots) {
    bool any = false;
    for (const char* name : {"teapot_102080", "teapot_1015056"}) {
        TestMesh teapot = loadTeapot(name);
        if (teapot.positions.empty()) continue;
        any = true;
        Summary summary = compare(teapot, 8192, 4321);
        std::printf("%s: at most %u loop turns for a group of eight\n", name,
                    summary.maxLockstepTurns);
        EXPECT_LT(summary.maxLockstepTurns, kSmallestKnownLoopLimit / 20) << name;
    }
    // The build makes them for these tests (bvh_tests.cmake): missing is a failure.
    ASSERT_TRUE(any) << "no big teapots in " << meshDir();
}
#endif
