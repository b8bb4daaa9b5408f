// Some GLs end a shader invocation after a fixed number of loop iterations, silently:
// Mesa 22's llvmpipe (Debian 12) after 65535, counted over all its loops and shared by
// the 8 invocations it runs side by side in one 256-bit vector. The invocation stops
// where it is, its pixel keeps whatever was written so far, and no error is raised.
// Mesa 25's llvmpipe (Debian 13) has no such limit; a GPU's driver has a watchdog that
// ends work by time instead.
//
// So the course does not guess the limit from the renderer's name: it measures it. A
// tiny shader loops a uniform number of times and the CPU works out how many of those
// iterations ran. The probe runs only when some work needs more iterations than the
// smallest limit any GL is known to have, and once per GL: the answer is remembered
// by GL_VENDOR + GL_RENDERER + GL_VERSION (which name the Mesa version), in memory and
// in $XDG_CACHE_HOME/gpu-ray-tracing-course/loop-limits.tsv (default ~/.cache). A cache
// that cannot be read or written is only a missed shortcut.
#pragma once
#include <cstddef>
#include <string>

#include "course/gl.h"

namespace course {

// No GL is known to stop loops sooner than Mesa 22's llvmpipe: work within this many
// iterations per invocation runs without a probe.
constexpr long long kSmallestKnownLoopLimit = 65535;
// How many iterations the probe asks for: far beyond every known limit.
constexpr long long kLoopProbeIterations = 262144;

struct LoopLimit {
    bool limited = false;      // false: all `probed` iterations ran
    long long iterations = 0;  // when limited: how many an invocation gets
    long long probed = 0;      // how many the probe asked for
    std::string driver;        // "llvmpipe (LLVM 15.0.6, 256 bits), OpenGL 4.5 ..."
    std::string text() const;  // "65535 loop iterations" or "no limit up to 262144 ..."
};

// The loop limit of the current context's shaders of `stage` (GL_COMPUTE_SHADER, or
// GL_FRAGMENT_SHADER for the GL 3.3 appendix): remembered, or measured now.
LoopLimit measureLoopLimit(GLenum stage);

// Work done in loops: every pixel's loops go through `count` things, at a cost of
// `iterationsEach` loop iterations each (e.g. 2: the nearest-hit search and the shadow
// ray's). The other fields are for the message.
struct LoopWork {
    std::string file;       // the mesh or scene file: "teapot.obj"
    size_t count;           // 102082
    std::string things;     // "triangles (with the floor's 2)"
    size_t iterationsEach;  // 2
    std::string wayOut;     // "A BVH renders this mesh."
    GLenum stage = GL_COMPUTE_SHADER;
};

// Refuses work that the measured limit would cut short: exit code 4, with a message
// naming the file, the count, the limit, the GL and the way out. Work within
// kSmallestKnownLoopLimit returns at once, and so does any work on a GL without a limit.
void checkLoopBudget(const LoopWork& work);

}  // namespace course
