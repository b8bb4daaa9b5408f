// The wavefront path tracer (Laine, Karras and Aila, "Megakernels Considered Harmful",
// 2013): chapter 22's path tracer cut at its rays. Instead of one kernel running each
// pixel's whole path (the megakernel, path.comp), each step is a kernel of its own, run
// over a queue of the paths that need it: trace their rays (extend), shade their hits
// (one kernel per kind of material), trace their shadow rays. Every invocation of a
// dispatch then does the same kind of work, at the price of keeping each path in memory
// between kernels, in a pool of path slots. The queues' sizes stay on the GPU: the host
// dispatches each kernel indirectly, over as many work groups as a small kernel
// computed from the size.
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "course/gpu_buffer.h"
#include "course/session.h"
#include "gpu_scene.h"

class Wavefront {
public:
    // Compiles the kernels with this scene's code (scene_code.glsl; a shading kernel
    // for each kind of material the scene has) and makes the pool of path slots and the
    // queues: a slot for every pixel of width x height, or as many as `paths` asks, or
    // as many as the GL's limits allow (asked, not assumed; --json: paths_in_flight).
    Wavefront(course::Session& session, const GpuScene& scene, const std::string& sceneCode,
              int width, int height, int paths);

    // Adds one sample to every pixel, as one dispatch of path.comp does: wave after
    // wave of at most a pool of pixels, each a camera ray for every pixel, rounds of
    // extend, shade and shadow until every path has ended (at most maxBounces + 1), and
    // the running mean. The PathParameters block must be bound and written.
    void addSample(int maxBounces);

private:
    void runWave(uint32_t firstPixel, uint32_t waveSize, int maxBounces);
    void setWave(uint32_t firstPixel, uint32_t waveSize, uint32_t rayQueue);
    void runOverQueue(const course::ShaderProgram& kernel, uint32_t queue);
    void computeDispatches();  // wavefront_dispatch.comp
    void empty(uint32_t firstQueue, uint32_t count);
    uint32_t queueSize(uint32_t queue) const;  // reads it back: waits for the GPU

    size_t pixels_;
    uint32_t poolSize_;
    course::GpuBuffer slots_;   // the pool: PathSlot each
    course::GpuBuffer queues_;  // the queues, then their items
    course::GpuBuffer wave_;    // WaveParameters
    const course::ShaderProgram& camera_;
    const course::ShaderProgram& extend_;
    std::vector<std::pair<uint32_t, const course::ShaderProgram*>> shaders_;  // by kind
    const course::ShaderProgram& shadow_;
    const course::ShaderProgram& accumulate_;
    const course::ShaderProgram& dispatch_;
};
