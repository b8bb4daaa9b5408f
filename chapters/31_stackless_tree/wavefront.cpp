#include "wavefront.h"

#include <algorithm>
#include <string>

#include "scene_code.h"
#include "shared.h"
#include "wavefront_layout.h"

namespace {

// The kinds of material the scene's shapes have: the shading kernels to compile.
std::vector<uint32_t> materialKinds(const GpuScene& scene) {
    uint32_t bits = materialKindBits(scene);
    std::vector<uint32_t> kinds;
    for (uint32_t kind = 0; kind < QUEUE_SHADOW - QUEUE_SHADE; ++kind)
        if (bits & (1u << kind)) kinds.push_back(kind);
    return kinds;
}

// The next ray queue is read back only every few rounds, since reading waits for the
// GPU: enough to stop --depth 1000 early, once Russian roulette has ended every path.
constexpr int kRoundsBetweenLooks = 8;

// The most path slots the GL allows: the pool and each queue's items must each fit in
// one storage block, and a queue of them in one indirect dispatch.
uint32_t mostPathSlots() {
    GLint64 mostBytes = 0;
    GLint mostGroups = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &mostBytes);
    glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &mostGroups);
    int64_t itemsBytes = mostBytes - QUEUE_COUNT * int64_t(sizeof(gpu::Queue));
    int64_t most = std::min<int64_t>({mostBytes / int64_t(sizeof(gpu::PathSlot)),
                                      itemsBytes / (QUEUE_COUNT * int64_t(sizeof(uint32_t))),
                                      int64_t(mostGroups) * QUEUE_GROUP_SIZE});
    return uint32_t(std::min<int64_t>(most, UINT32_MAX));
}

}  // namespace

Wavefront::Wavefront(course::Session& session, const GpuScene& scene,
                     const std::string& sceneCode, int width, int height, int paths)
    : pixels_(size_t(width) * height),
      camera_(session.loadCompute("wavefront_camera.comp", {{"scene_code.glsl", sceneCode}})),
      extend_(session.loadCompute("wavefront_extend.comp", {{"scene_code.glsl", sceneCode}})),
      shadow_(session.loadCompute("wavefront_shadow.comp", {{"scene_code.glsl", sceneCode}})),
      accumulate_(session.loadCompute("wavefront_accumulate.comp",
                                      {{"scene_code.glsl", sceneCode}})),
      dispatch_(session.loadCompute("wavefront_dispatch.comp",
                                    {{"scene_code.glsl", sceneCode}})) {
    size_t wanted = paths > 0 ? std::min(pixels_, size_t(paths)) : pixels_;
    poolSize_ = uint32_t(std::min<size_t>(wanted, mostPathSlots()));
    session.stats().set("paths_in_flight", double(poolSize_));
    slots_ = course::GpuBuffer(size_t(poolSize_) * sizeof(gpu::PathSlot));
    queues_ = course::GpuBuffer(QUEUE_COUNT * (sizeof(gpu::Queue) +
                                               size_t(poolSize_) * sizeof(uint32_t)));
    wave_ = course::GpuBuffer(sizeof(gpu::WaveParameters));
    for (uint32_t kind : materialKinds(scene)) {
        std::string define = "#define SHADE_KIND " + std::to_string(kind) + "\n";
        shaders_.push_back({kind, &session.loadCompute("wavefront_shade.comp",
                                                        {{"scene_code.glsl", sceneCode},
                                                         {"shade_kind.glsl", define}})});
    }
    slots_.bindStorage(PATH_SLOTS_BINDING);
    queues_.bindStorage(QUEUES_BINDING);
    wave_.bindUniform(WAVE_BINDING);
}

void Wavefront::addSample(int maxBounces) {
    for (size_t first = 0; first < pixels_; first += poolSize_)
        runWave(uint32_t(first), uint32_t(std::min<size_t>(poolSize_, pixels_ - first)),
                maxBounces);
}

// --8<-- [start:sample]
void Wavefront::runWave(uint32_t firstPixel, uint32_t waveSize, int maxBounces) {
    uint32_t rays = QUEUE_RAYS;  // the ray queue the kernels read; they fill the other
    empty(0, QUEUE_COUNT);
    setWave(firstPixel, waveSize, rays);
    camera_.dispatchCovering(int(waveSize));  // camera rays into `rays`
    for (int round = 0; round <= maxBounces; ++round) {
        computeDispatches();
        runOverQueue(extend_, rays);  // hits into the shading queues
        computeDispatches();
        for (auto& [kind, shade] : shaders_)
            runOverQueue(*shade, QUEUE_SHADE + kind);  // into QUEUE_SHADOW, next rays
        computeDispatches();
        runOverQueue(shadow_, QUEUE_SHADOW);
        // Every ray traced, every hit shaded, every shadow ray traced: empty those
        // queues (after the kernels' writes), and read the other ray queue next.
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        empty(rays, 1);
        empty(QUEUE_SHADE, QUEUE_COUNT - QUEUE_SHADE);
        rays = 1 - rays;
        setWave(firstPixel, waveSize, rays);
        if ((round + 1) % kRoundsBetweenLooks == 0 && queueSize(rays) == 0) break;
    }
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    accumulate_.dispatchCovering(int(waveSize));
}
// --8<-- [end:sample]

void Wavefront::setWave(uint32_t firstPixel, uint32_t waveSize, uint32_t rayQueue) {
    gpu::WaveParameters wave{firstPixel, waveSize, poolSize_, rayQueue};
    wave_.write(&wave, sizeof wave);
}

void Wavefront::runOverQueue(const course::ShaderProgram& kernel, uint32_t queue) {
    kernel.use();
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, queues_.id());
    glDispatchComputeIndirect(queue * sizeof(gpu::Queue) + offsetof(gpu::Queue, groupsX));
}

// What the last kernel wrote, the next one reads: as storage, and as a dispatch command.
void Wavefront::computeDispatches() {
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    dispatch_.dispatchCovering(QUEUE_COUNT);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
}

void Wavefront::empty(uint32_t firstQueue, uint32_t count) {
    const uint32_t zero = 0;
    // glClearBufferSubData is OpenGL 4.3, as the chapter asks (the named form is 4.5).
    glBindBuffer(GL_COPY_WRITE_BUFFER, queues_.id());
    glClearBufferSubData(GL_COPY_WRITE_BUFFER, GL_R32UI, firstQueue * sizeof(gpu::Queue),
                         count * sizeof(gpu::Queue), GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
}

uint32_t Wavefront::queueSize(uint32_t queue) const {
    gpu::Queue q{};
    queues_.read(&q, sizeof q, queue * sizeof(gpu::Queue));
    return q.size;
}
