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

// One kernel that follows each pixel's paths, or a kernel per step over queues.
enum class Kernel { Megakernel, Wavefront };

// From the command line.
struct KernelOptions {
    Kernel kernel = Kernel::Megakernel;  // --kernel megakernel|wavefront
    int paths = 0;  // --paths: the wavefront's pool of path slots; 0: as many as fit
    int samplesPerDispatch = kMostSamplesPerDispatch;  // --samples-per-dispatch: at most
    int batches = 1;  // --batches: render --spp in this many groups of dispatches
};
void declareKernelOptions(course::CommandLine& cli, KernelOptions& options);

// How rays find the triangles: none to find, the tree (walks of no length known in
// advance), or every one tested in the shapes' loops (--brute-force).
enum class TriangleSearch { None, Tree, EveryTriangle };
enum class Invocation { WholePaths, OneRay };  // what one invocation traces: paths or a ray

// The loops one sample of a pixel runs, for the GL's loop limit (loop_budget.h).
struct PathLoops {
    std::string sceneFile;
    size_t shapes;  // shapes a ray tests in loops: spheres and quads, or every shape
    TriangleSearch triangles;
    int depth;      // --depth
    Invocation invocation;
};

// Exit code 4 if the GL's loop limit (measured, if the loops need more iterations than
// every GL allows) would cut a sample's loops short and the picture would be wrong.
void checkPathLoops(const PathLoops& loops);

// How many samples each dispatch of the megakernel adds to every pixel of `pixels`:
// as many as --samples-per-dispatch, as fit the loop limit (or for a tree, as many as a
// first try: checked_dispatch.h), and as keep one dispatch short; 1 for the wavefront
// and the views, which take one sample a dispatch.
int samplesPerDispatch(const KernelOptions& options, const PathLoops& loops, size_t pixels);

// Whether each dispatch must find out if the GL cut it short: the megakernel's walks of
// a tree (no length known in advance) on a GL with a loop limit (measured).
bool dispatchesNeedChecks(const PathLoops& loops);

// ESTIMATOR_NEE, _BSDF or _MIS (shared.h) for an --estimator word.
int estimatorCode(const std::string& name);
