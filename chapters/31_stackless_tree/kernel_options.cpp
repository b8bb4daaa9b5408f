#include "kernel_options.h"

#include <algorithm>

#include "course/loop_budget.h"
#include "shared.h"  // ESTIMATOR_*

namespace {

// --8<-- [start:limits]
// Loop iterations a bounce may run besides its shape loops: the bounce loop's own turn
// and the environment's two binary searches (at most 32 steps each).
constexpr long long kOtherIterationsPerBounce = 1 + 64;

// The most paths one dispatch traces. A GPU's driver ends work that runs for seconds
// (its watchdog), and a big image already gives every lane work: 2^22 paths is a
// 2048 x 2048 image's single sample, or 256 x 256's 64.
constexpr long long kMostPathsPerDispatch = 1 << 22;
// --8<-- [end:limits]

}  // namespace

void declareKernelOptions(course::CommandLine& cli, KernelOptions& options) {
    cli.choice("--kernel", "one kernel per path, or one per step over queues of paths",
               {"megakernel", "wavefront"}, &options.kernel);
    cli.option("--paths", "N", "wavefront: paths in flight at once, the image in waves of "
               "N pixels (default: every pixel, or as many as the GL allows)",
               &options.paths, 1, 1 << 30);
    cli.option("--samples-per-dispatch", "K", "megakernel: at most K samples of a pixel in "
               "one dispatch, a new path as soon as one ends (default 64; the same image)",
               &options.samplesPerDispatch, 1, 1024);
    cli.option("--batches", "B", "render --spp in B groups of dispatches, waiting for "
               "the GPU between them (the same image)", &options.batches, 1, 1 << 20);
}

void checkPathLoops(const PathLoops& loops) {
    // Each bounce loops over the shapes twice (nearest hit, shadow ray): with the
    // tree, only spheres and quads, and its own steps are a few hundred per ray. (A
    // wavefront kernel traces one ray: a path's bounces are rounds of dispatches.)
    size_t rounds = loops.invocation == Invocation::WholePaths ? size_t(loops.depth) + 1 : 1;
    const char* wayOut = loops.triangles == TriangleSearch::EveryTriangle
                             ? "Without --brute-force, the tree renders it."
                             : "Fewer spheres and quads, or a lower --depth, fit.";
    course::checkLoopBudget({loops.sceneFile, loops.shapes, "shapes tested in loops",
                             2 * rounds, wayOut});
}

// --8<-- [start:per_dispatch]
int samplesPerDispatch(const KernelOptions& options, const PathLoops& loops, size_t pixels) {
    if (loops.invocation == Invocation::OneRay) return 1;
    long long most = std::min<long long>(options.samplesPerDispatch,
                                         kMostPathsPerDispatch / std::max<size_t>(pixels, 1));
    // A walk of the tree has no length known in advance, so no count of samples is sure
    // to fit a loop limit: where the GL has one, each dispatch checks whether it was cut
    // short, and runs again with fewer samples (checked_dispatch.h). Spheres and quads
    // are tested a known number of times: as many samples as fit.
    if (loops.triangles != TriangleSearch::Tree) {
        long long perSample = (loops.depth + 1LL) *
                              (2LL * loops.shapes + kOtherIterationsPerBounce);
        most = std::min(most, course::kSmallestKnownLoopLimit / perSample);
    }
    return int(std::max(most, 1LL));
}
// --8<-- [end:per_dispatch]

bool dispatchesNeedChecks(const PathLoops& loops) {
    return loops.invocation == Invocation::WholePaths &&
           loops.triangles == TriangleSearch::Tree &&
           course::measureLoopLimit(GL_COMPUTE_SHADER).limited;
}

int estimatorCode(const std::string& name) {
    return name == "nee" ? ESTIMATOR_NEE : name == "bsdf" ? ESTIMATOR_BSDF : ESTIMATOR_MIS;
}
