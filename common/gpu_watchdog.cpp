#include "course/gpu_watchdog.h"

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <mutex>
#include <thread>

#include "course/error.h"
#include "course/gl.h"
#include "course/render_progress.h"

namespace course {

double gpuStepSeconds() {
    const char* setting = std::getenv("COURSE_GPU_TIMEOUT_SECONDS");
    double seconds = setting ? std::atof(setting) : 0.0;
    return seconds > 0.0 ? seconds : kDefaultGpuStepSeconds;
}

double gpuCompileSeconds() { return 10.0 * gpuStepSeconds(); }

namespace {

using Clock = std::chrono::steady_clock;

[[noreturn]] void failGpuStalled(double limit) {
    std::fprintf(stderr,
                 "error: the GPU finished no step of the render for %.0f s: a shader "
                 "probably loops forever (check its loop conditions). If the work is "
                 "only that slow, COURSE_GPU_TIMEOUT_SECONDS=%.0f allows more.\n",
                 limit, limit * 10.0);
    // Not a normal return: tearing down a context whose GPU work is still running can
    // block forever too. Nothing has been written yet.
    std::_Exit(static_cast<int>(ExitCode::GlProblem));
}

[[noreturn]] void failCompileStalled(const std::string& program, double limit) {
    std::fprintf(stderr,
                 "error: the GL spent %.0f s compiling %s without finishing (a compile "
                 "may take ten times COURSE_GPU_TIMEOUT_SECONDS). If this machine is "
                 "only that slow or that busy, COURSE_GPU_TIMEOUT_SECONDS=%.0f allows "
                 "more.\n",
                 limit, program.c_str(), gpuStepSeconds() * 10.0);
    std::_Exit(static_cast<int>(ExitCode::GlProblem));
}

// The watchdog's state: the time of the last progress, read by its thread, and the
// program being compiled, if one is (empty when not).
std::mutex progressMutex;
std::condition_variable progressChanged;
Clock::time_point lastProgress = Clock::now();
bool watching = false;
std::string compiling;

void noteProgress() {
    std::lock_guard<std::mutex> lock(progressMutex);
    lastProgress = Clock::now();
}

// Fences behind the queued steps, oldest first (main thread only). A few hundred are
// plenty to see progress; past that the oldest are let go.
std::deque<GLsync> stepFences;
constexpr size_t kMostFences = 256;

std::thread watcher;

}  // namespace

void gpuStepQueued() {
    noteProgress();
    RenderProgress::stepTaken();
    if (stepFences.size() == kMostFences) {
        glDeleteSync(stepFences.front());
        stepFences.pop_front();
    }
    stepFences.push_back(glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0));
}

void waitForGpu() {
    const double limit = gpuStepSeconds();
    stepFences.push_back(glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0));
    auto progress = Clock::now();
    while (!stepFences.empty()) {
        GLenum state = glClientWaitSync(stepFences.front(), GL_SYNC_FLUSH_COMMANDS_BIT,
                                        100'000'000);  // nanoseconds: 0.1 s
        if (state == GL_ALREADY_SIGNALED || state == GL_CONDITION_SATISFIED) {
            glDeleteSync(stepFences.front());
            stepFences.pop_front();
            progress = Clock::now();
            noteProgress();
            continue;
        }
        std::chrono::duration<double> stalled = Clock::now() - progress;
        if (state == GL_WAIT_FAILED || stalled.count() > limit) failGpuStalled(limit);
    }
}

GpuWatchdog::GpuWatchdog() {
    noteProgress();
    {
        std::lock_guard<std::mutex> lock(progressMutex);
        watching = true;
    }
    watcher = std::thread([] {
        auto duration = [](double seconds) {
            return std::chrono::duration_cast<Clock::duration>(
                std::chrono::duration<double>(seconds));
        };
        const double stepLimit = gpuStepSeconds(), compileLimit = gpuCompileSeconds();
        std::unique_lock<std::mutex> lock(progressMutex);
        while (watching) {
            const bool compile = !compiling.empty();
            const auto deadline = lastProgress + duration(compile ? compileLimit : stepLimit);
            if (Clock::now() >= deadline) {
                if (compile) failCompileStalled(compiling, compileLimit);
                failGpuStalled(stepLimit);
            }
            progressChanged.wait_until(lock, deadline);
        }
    });
}

// Starting and ending a compile are both progress: the step after it gets a whole
// step's time.
ShaderCompileAllowance::ShaderCompileAllowance(const std::string& program) {
    {
        std::lock_guard<std::mutex> lock(progressMutex);
        lastProgress = Clock::now();
        compiling = program.empty() ? "a shader" : program;
    }
    progressChanged.notify_all();
}

ShaderCompileAllowance::~ShaderCompileAllowance() {
    {
        std::lock_guard<std::mutex> lock(progressMutex);
        lastProgress = Clock::now();
        compiling.clear();
    }
    progressChanged.notify_all();
}

GpuWatchdog::~GpuWatchdog() {
    {
        std::lock_guard<std::mutex> lock(progressMutex);
        watching = false;
    }
    progressChanged.notify_all();
    watcher.join();
}

}  // namespace course
