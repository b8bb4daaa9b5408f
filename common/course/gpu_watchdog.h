// A render that never ends, ended: a shader that loops forever must not hang the
// program (Mesa 25's llvmpipe and most GPUs let it run; Mesa 22's cuts loops short).
//
// The course's renders are made of steps of bounded work: one sample per pixel per
// dispatch. So the watchdog judges progress, not the render's length: while it is on
// (Session::timeRender turns it on), the program ends with exit code 4 and a message
// when no step has finished for COURSE_GPU_TIMEOUT_SECONDS (default 30). A render of a
// thousand quick steps runs as long as it needs; one endless step ends in seconds.
#pragma once
#include <string>

namespace course {

// How long a step may take: COURSE_GPU_TIMEOUT_SECONDS, default kDefaultGpuStepSeconds.
constexpr double kDefaultGpuStepSeconds = 30.0;
double gpuStepSeconds();

// Call after queuing a step of GPU work (ShaderProgram::dispatchCovering does). Its call
// returning is progress (some GLs, llvmpipe among them, run a dispatch inside the call),
// and a fence behind it lets waitForGpu() see the step finish on GLs that queue it.
void gpuStepQueued();

// Blocks until the GPU has finished all queued work; ends the program with exit code 4
// and a message when no step finishes within gpuStepSeconds().
void waitForGpu();

// Some GLs (Mesa's llvmpipe) compile a compute shader on the CPU at its first dispatch,
// which for a large shader on a busy machine can take longer than a step may. While one
// lives (ShaderProgram::compileBeforeFirstDispatch), the watchdog allows a compile
// gpuCompileSeconds(), ten times a step, and names the program if even that runs out.
double gpuCompileSeconds();
class ShaderCompileAllowance {
public:
    explicit ShaderCompileAllowance(const std::string& program);
    ~ShaderCompileAllowance();
    ShaderCompileAllowance(const ShaderCompileAllowance&) = delete;
    ShaderCompileAllowance& operator=(const ShaderCompileAllowance&) = delete;
};

// While one lives, a stalled GPU ends the program (a thread of its own watches: the
// main thread may be stuck inside a GL call).
class GpuWatchdog {
public:
    GpuWatchdog();
    ~GpuWatchdog();
    GpuWatchdog(const GpuWatchdog&) = delete;
    GpuWatchdog& operator=(const GpuWatchdog&) = delete;
};

}  // namespace course
