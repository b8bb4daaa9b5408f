#include "course/render_progress.h"

#include <chrono>
#include <cstdio>

#ifdef _WIN32
#include <io.h>
#define COURSE_ISATTY _isatty
#define COURSE_FILENO _fileno
#else
#include <unistd.h>
#define COURSE_ISATTY isatty
#define COURSE_FILENO fileno
#endif

namespace course {

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kQuietSeconds = 2.0;     // shorter renders say nothing
constexpr double kRedrawSeconds = 0.25;   // at most four lines a second

struct Shown {
    const unsigned* samplesDone = nullptr;
    int samplesWanted = 0;
    Clock::time_point started;
    Clock::time_point lastDrawn;
    bool drawn = false;
};
Shown* shown = nullptr;  // the render in progress, when it is shown

double secondsSince(Clock::time_point then) {
    return std::chrono::duration<double>(Clock::now() - then).count();
}

}  // namespace

RenderProgress::RenderProgress(const unsigned& samplesDone, int samplesWanted) {
    if (!COURSE_ISATTY(COURSE_FILENO(stderr)) || samplesWanted <= 0) return;
    shown = new Shown{&samplesDone, samplesWanted, Clock::now(), Clock::now(), false};
}

RenderProgress::~RenderProgress() {
    if (!shown) return;
    if (shown->drawn) std::fprintf(stderr, "\r\033[K");  // the line goes: the render is done
    std::fflush(stderr);
    delete shown;
    shown = nullptr;
}

void RenderProgress::stepTaken() {
    if (!shown) return;
    double elapsed = secondsSince(shown->started);
    if (elapsed < kQuietSeconds || secondsSince(shown->lastDrawn) < kRedrawSeconds) return;
    shown->lastDrawn = Clock::now();
    shown->drawn = true;
    unsigned done = *shown->samplesDone;
    double perSecond = done / elapsed;
    double left = perSecond > 0.0 ? (shown->samplesWanted - double(done)) / perSecond : 0.0;
    std::fprintf(stderr,
                 "\r\033[Krendering: %u of %d samples a pixel (%.1f a second), about %.0f s left",
                 done, shown->samplesWanted, perSecond, left > 0.0 ? left : 0.0);
    std::fflush(stderr);
}

}  // namespace course
