// The wavefront path tracer (Laine, Karras and Aila, "Megakernels Considered Harmful",
// 2013): chapter 19's path tracer cut at its rays. Instead of one kernel running each
// pixel's whole path (the megakernel, path.comp), each step is a kernel of its own, run
// over a queue of the paths that need it: trace their rays (extend), shade their hits
// (one kernel per kind of material), trace their shadow rays. Every invocation of a
// dispatch then does the same kind of work, at the price of storing each path in memory
// between kernels. The queues' sizes stay on the GPU: the host dispatches each kernel
// indirectly, over as many work groups as a small kernel computed from the size.
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

#include "course/gpu_buffer.h"
#include "course/session.h"
#include "gpu_scene.h"

class Wavefront {
public:
    // Compiles the kernels with this scene's code (scene_code.glsl; a shading kernel
    // for each kind of material the scene has) and makes the paths' memory and the
    // queues for width x height pixels.
    Wavefront(course::Session& session, const GpuScene& scene, const std::string& sceneCode,
              int width, int height);

    // Adds one sample to every pixel, as one dispatch of path.comp does: a camera ray
    // each, then rounds of extend, shade and shadow until every path has ended (at most
    // maxBounces + 1 rounds), then the running mean. The PathParameters block must be
    // bound and written.
    void addSample(int maxBounces);

private:
    void runOverQueue(const course::ShaderProgram& kernel, uint32_t queue);
    void computeDispatches();  // wavefront_dispatch.comp
    void empty(uint32_t firstQueue, uint32_t count);
    uint32_t queueSize(uint32_t queue) const;  // reads it back: waits for the GPU

    int width_, height_;
    course::GpuBuffer slots_;   // each pixel's PathSlot
    course::GpuBuffer queues_;  // the queues, then their items
    const course::ShaderProgram& camera_;
    const course::ShaderProgram& extend_;
    std::vector<std::pair<uint32_t, const course::ShaderProgram*>> shaders_;  // by kind
    const course::ShaderProgram& shadow_;
    const course::ShaderProgram& accumulate_;
    const course::ShaderProgram& dispatch_;
};
