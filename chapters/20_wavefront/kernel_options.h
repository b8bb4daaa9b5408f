// How the path tracer runs: one kernel that follows each pixel's paths (the megakernel,
// path.comp) or a kernel per step over queues of paths (the wavefront, wavefront.h);
// the wavefront's pool of paths; and how many samples one dispatch of the megakernel
// adds to every pixel, with the loops a sample runs checked against the GL's limit.
#pragma once
#include <cstddef>
#include <string>

#include "course/cli.h"

// The most samples a dispatch of the megakernel adds to a pixel. A lane whose path ends
// starts the pixel's next sample at once (path regeneration, path.comp), so its group
// waits for the longest path only at the end of the dispatch: measured on llvmpipe, the
// Cornell box runs 1.6 times as fast with 8 samples a dispatch, 1.9 with 32, 2.0 with 64.
constexpr int kMostSamplesPerDispatch = 64;

// From the command line.
struct KernelOptions {
    std::string kernel = "megakernel";  // --kernel: megakernel or wavefront
    int paths = 0;  // --paths: the wavefront's pool of path slots; 0: as many as fit
    int samplesPerDispatch = kMostSamplesPerDispatch;  // --samples-per-dispatch: at most
};
void declareKernelOptions(course::CommandLine& cli, KernelOptions& options);

// The loops one sample of a pixel runs, for the GL's loop limit (loop_budget.h).
struct PathLoops {
    std::string sceneFile;
    size_t shapes;     // shapes a ray tests in loops: spheres and quads, or every shape
    bool bruteForce;   // --brute-force: the triangles are among `shapes`
    bool tree;         // triangles found through the tree: walks of no fixed length
    int depth;         // --depth
    bool wholePaths;   // one invocation traces whole paths: the megakernel's radiance
};

// Exit code 4 if the GL's loop limit (measured, if the loops need more iterations than
// every GL allows) would cut a sample's loops short and the picture would be wrong.
void checkPathLoops(const PathLoops& loops);

// How many samples each dispatch of the megakernel adds to every pixel of `pixels`:
// as many as --samples-per-dispatch, as fit the loop limit, and as keep one dispatch
// short; 1 for the wavefront and the views, which take one sample a dispatch.
int samplesPerDispatch(const KernelOptions& options, const PathLoops& loops, size_t pixels);
