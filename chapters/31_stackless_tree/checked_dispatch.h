// Dispatches of the megakernel that find out whether the GL cut their loops short, and
// if it did, run again from where they started with half as many samples (chapter 30).
// Chapter 22 could not know how long a walk of the tree would take, so on a GL with a
// loop limit a tree scene got one sample a dispatch. Here every dispatch checks itself
// instead: path.comp counts the invocations that a cut reached (loopsCutShort), and
// this class keeps a copy of what a dispatch changes, to put back when it must be redone.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "course/gpu_buffer.h"
#include "course/stats.h"

class CheckedDispatch {
public:
    // `changed`: the buffers a dispatch of the megakernel writes (the image, the random
    // states, the ray counts); `samples`: the most samples a dispatch may add to each
    // pixel; `check`: whether the GL has a loop limit (without one, nothing is kept or
    // read back, and a dispatch runs as in chapter 22). `sceneFile` names the failure.
    CheckedDispatch(std::vector<const course::GpuBuffer*> changed, int samples, bool check,
                    std::string sceneFile);

    // Runs dispatch(n), which adds n samples to every pixel, for n = min(wanted, the
    // samples a dispatch may add), and returns n. If the GL cut the dispatch short, first
    // halves the samples a dispatch may add, puts the buffers back and runs it again;
    // exit code 4 when even one sample a dispatch is cut short.
    int add(int wanted, const std::function<void(int)>& dispatch);

    // --json: samples_per_dispatch (the last dispatches', at most --spp) and
    // dispatches_redone.
    void record(course::Stats& stats, int spp) const;

private:
    void keep();     // changed -> copies
    void putBack();  // copies -> changed
    std::vector<const course::GpuBuffer*> changed_;
    std::vector<course::GpuBuffer> copies_;
    course::GpuBuffer cutShort_;  // path.comp's atomic counter cutShortInvocations
    int samples_;
    bool check_;
    std::string sceneFile_;
    int redone_ = 0;
};
