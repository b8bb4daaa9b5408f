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

// The watchdog's state: the time of the last progress, read by its thread.
std::mutex progressMutex;
std::condition_variable progressChanged;
Clock::time_point lastProgress = Clock::now();
bool watching = false;

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
    const double limit = gpuStepSeconds();
    watcher = std::thread([limit] {
        auto allowed = std::chrono::duration_cast<Clock::duration>(
            std::chrono::duration<double>(limit));
        std::unique_lock<std::mutex> lock(progressMutex);
        while (watching) {
            if (Clock::now() >= lastProgress + allowed) failGpuStalled(limit);
            progressChanged.wait_until(lock, lastProgress + allowed);
        }
    });
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
