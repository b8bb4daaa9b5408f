#include "wavefront.h"

#include <string>

#include "shared.h"
#include "wavefront_layout.h"

namespace {

// The kinds of material the scene's shapes have: the shading kernels to compile.
std::vector<uint32_t> materialKinds(const GpuScene& scene) {
    uint32_t bits = 0;
    for (const gpu::Material& m : scene.materials) bits |= 1u << m.kind;
    std::vector<uint32_t> kinds;
    for (uint32_t kind = 0; kind < QUEUE_SHADOW - QUEUE_SHADE; ++kind)
        if (bits & (1u << kind)) kinds.push_back(kind);
    return kinds;
}

// The next ray queue is read back only every few rounds, since reading waits for the
// GPU: enough to stop --depth 1000 early, once Russian roulette has ended every path.
constexpr int kRoundsBetweenLooks = 8;

}  // namespace

Wavefront::Wavefront(course::Session& session, const GpuScene& scene,
                     const std::string& sceneCode, int width, int height)
    : width_(width),
      height_(height),
      slots_(size_t(width) * height * sizeof(gpu::PathSlot)),
      queues_(QUEUE_COUNT * (sizeof(gpu::Queue) + size_t(width) * height * sizeof(uint32_t))),
      camera_(session.loadCompute("wavefront_camera.comp", {{"scene_code.glsl", sceneCode}})),
      extend_(session.loadCompute("wavefront_extend.comp", {{"scene_code.glsl", sceneCode}})),
      shadow_(session.loadCompute("wavefront_shadow.comp", {{"scene_code.glsl", sceneCode}})),
      accumulate_(session.loadCompute("wavefront_accumulate.comp",
                                      {{"scene_code.glsl", sceneCode}})),
      dispatch_(session.loadCompute("wavefront_dispatch.comp",
                                    {{"scene_code.glsl", sceneCode}})) {
    for (uint32_t kind : materialKinds(scene)) {
        std::string define = "#define SHADE_KIND " + std::to_string(kind) + "\n";
        shaders_.push_back({kind, &session.loadCompute("wavefront_shade.comp",
                                                        {{"scene_code.glsl", sceneCode},
                                                         {"shade_kind.glsl", define}})});
    }
    slots_.bindStorage(PATH_SLOTS_BINDING);
    queues_.bindStorage(QUEUES_BINDING);
}

// --8<-- [start:sample]
void Wavefront::addSample(int maxBounces) {
    // What a kernel wrote, the next one reads: as storage, and as a dispatch command.
    auto barrier = [] {
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT |
                        GL_BUFFER_UPDATE_BARRIER_BIT);
    };
    uint32_t rays = QUEUE_RAYS;  // the ray queue the kernels read; they fill the other
    empty(0, QUEUE_COUNT);
    camera_.set("rayQueue", rays);
    camera_.dispatchCovering(width_, height_);
    for (int round = 0; round <= maxBounces; ++round) {
        barrier();
        computeDispatches();
        extend_.set("rayQueue", rays);
        runOverQueue(extend_, rays);  // hits into the shading queues
        computeDispatches();
        for (auto& [kind, shade] : shaders_) {
            shade->set("rayQueue", rays);
            runOverQueue(*shade, QUEUE_SHADE + kind);  // into QUEUE_SHADOW, next rays
        }
        computeDispatches();
        runOverQueue(shadow_, QUEUE_SHADOW);
        barrier();
        empty(rays, 1);  // all traced
        empty(QUEUE_SHADE, QUEUE_COUNT - QUEUE_SHADE);  // all shaded, all shadows traced
        rays = 1 - rays;
        if ((round + 1) % kRoundsBetweenLooks == 0 && queueSize(rays) == 0) break;
    }
    barrier();
    accumulate_.dispatchCovering(width_, height_);
}
// --8<-- [end:sample]

void Wavefront::runOverQueue(const course::ShaderProgram& kernel, uint32_t queue) {
    kernel.use();
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, queues_.id());
    glDispatchComputeIndirect(queue * sizeof(gpu::Queue) + offsetof(gpu::Queue, groupsX));
}

void Wavefront::computeDispatches() {
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    dispatch_.dispatchCovering(QUEUE_COUNT);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
}

void Wavefront::empty(uint32_t firstQueue, uint32_t count) {
    const uint32_t zero = 0;
    glClearNamedBufferSubData(queues_.id(), GL_R32UI, firstQueue * sizeof(gpu::Queue),
                              count * sizeof(gpu::Queue), GL_RED_INTEGER, GL_UNSIGNED_INT,
                              &zero);
}

uint32_t Wavefront::queueSize(uint32_t queue) const {
    gpu::Queue q{};
    queues_.read(&q, sizeof q, queue * sizeof(gpu::Queue));
    return q.size;
}
