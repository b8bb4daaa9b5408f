#include "motion.h"

#include <chrono>
#include <cstdint>
#include <vector>

#include "course/error.h"

namespace {

double millisecondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
        .count();
}

// The GPU's copy of `items` written over (its size stays the same).
template <typename T>
void writeOver(course::GpuBuffer& buffer, const std::vector<T>& items) {
    if (!items.empty()) buffer.write(items.data(), items.size() * sizeof(T));
}

// The SAH cost of a tree built afresh over the object's triangles as they are now.
double rebuiltSahCost(const GpuScene& gpu, const PackedObject& object) {
    std::vector<glm::vec3> corners;
    const size_t end = object.firstTriangle + object.triangleCount;
    for (size_t t = object.firstTriangle; t < end; ++t)
        for (int k = 0; k < 3; ++k)
            corners.emplace_back(gpu.positions[gpu.triangles[t].corners[k]]);
    std::vector<uint32_t> indices(corners.size());
    for (size_t i = 0; i < indices.size(); ++i) indices[i] = uint32_t(i);
    return buildBvh(corners, indices).stats.sahCost;
}

}  // namespace

void declareMotionOptions(course::CommandLine& cli, MotionOptions& options) {
    cli.option("--instant", "S", "a still at S of the shutter's interval (0: it opens, 1: "
               "it closes) instead of the blur over all of it", &options.instant);
    cli.option("--animate", "F", "window: the instances move frame by frame, F frames "
               "from the shutter's opening to its closing and back, the top level built "
               "again each frame", &options.animationFrames, 1, 100000);
    cli.option("--twist", "DEGREES", "twist every object about its upright middle, by "
               "DEGREES at its top when the shutter closes, its tree refitted (with "
               "--instant or --animate)", &options.twistDegrees);
}

Motion::Motion(GpuScene& gpu, const course::SceneFile& scene, SceneBuffers& buffers,
               const MotionOptions& options, bool window)
    : gpu_(gpu), scene_(scene), buffers_(buffers), options_(options),
      rest_{gpu.positions, gpu.normals} {
    using course::ExitCode;
    if (options.instant != kWholeShutter && (options.instant < 0.0f || options.instant > 1.0f))
        throw course::Failure(ExitCode::BadUsage, "--instant: S is a fraction of the "
                              "shutter's interval, from 0 to 1");
    if (animates() && !window)
        throw course::Failure(ExitCode::BadUsage, "--animate plays the motion in the "
                              "window (--window); headless, --instant S renders one frame");
    if (options.twistDegrees != 0.0f && options.instant == kWholeShutter && !animates())
        throw course::Failure(ExitCode::BadUsage, "--twist deforms the objects at an "
                              "instant (--instant or --animate): a blurred picture keeps "
                              "their shape");
}

float Motion::firstInstant() const {
    if (options_.instant != kWholeShutter || animates())
        return std::max(options_.instant, 0.0f);
    const course::SceneCamera& camera = scene_.camera;
    return camera.shutterClose > camera.shutterOpen ? kWholeShutter : 0.0f;
}

float Motion::instantOfFrame(int frame) const {
    const int frames = options_.animationFrames, phase = frame % (2 * frames);
    return float(phase <= frames ? phase : 2 * frames - phase) / float(frames);
}

// --8<-- [start:show]
void Motion::show(float instant) {
    // 1. The objects' shapes at the instant, and their trees refitted around them (and,
    //    to compare, a tree built afresh over the same triangles: not drawn).
    if (options_.twistDegrees != 0.0f && instant != kWholeShutter) {
        twistObjects(gpu_, rest_, options_.twistDegrees * instant);
        refitCost_ = rebuiltCost_ = refitMs_ = rebuildMs_ = 0.0;
        for (const PackedObject& object : gpu_.objects) {
            auto start = std::chrono::steady_clock::now();
            refitTree(gpu_, object);
            refitMs_ += millisecondsSince(start);
            refitCost_ += treeSahCost(gpu_.bvh.nodes, object.firstNode, object.nodeCount);
            start = std::chrono::steady_clock::now();
            rebuiltCost_ += rebuiltSahCost(gpu_, object);
            rebuildMs_ += millisecondsSince(start);
        }
        writeOver(buffers_.positions, gpu_.positions);
        writeOver(buffers_.normals, gpu_.normals);
    }
    // 2. The instances at the instant, and the top level over them built again.
    placeInstances(gpu_, scene_, instant);
    writeOver(buffers_.bvhNodes, gpu_.bvh.nodes);
    writeOver(buffers_.instances, gpu_.instances);
    shown_ = instant;
    ++framesShown_;
}
// --8<-- [end:show]

void Motion::record(course::Stats& json) const {
    json.set("instant", double(shown_));
    json.set("frames_shown", double(framesShown_));
    if (options_.twistDegrees == 0.0f) return;
    json.set("twist_degrees", double(options_.twistDegrees));
    json.set("object_sah_cost", refitCost_);
    json.set("rebuilt_sah_cost", rebuiltCost_);
    json.set("refit_ms", refitMs_);
    json.set("rebuild_ms", rebuildMs_);
    json.set("instance_tree_ms", gpu_.instanceStats.instanceTreeMilliseconds);
}
