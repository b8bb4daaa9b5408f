// How long the GPU itself worked, measured by the GPU: two timestamp queries
// (glQueryCounter with GL_TIMESTAMP, core since GL 3.3), one before the commands to
// time and one after. The CPU's clock around a dispatch measures only how long it took
// to queue it; the GPU runs it later, and writes each timestamp when it gets there.
// (GL_TIME_ELAPSED would do on a GPU, but llvmpipe counts only drawing in it, not
// compute shaders: it gives 0 for this chapter's renders. Timestamps work on both.)
#pragma once
#include "course/gl.h"
#include "course/gpu_buffer.h"
#include "course/session.h"

class GpuTimer {
public:
    GpuTimer() { glGenQueries(2, queries_); }
    ~GpuTimer() { glDeleteQueries(2, queries_); }
    GpuTimer(const GpuTimer&) = delete;
    GpuTimer& operator=(const GpuTimer&) = delete;

    // Before and after the commands to time.
    void start() { glQueryCounter(queries_[0], GL_TIMESTAMP); }
    void stop() { glQueryCounter(queries_[1], GL_TIMESTAMP); }
    // Waits for the GPU to get to stop(), then gives the time between, in milliseconds.
    double milliseconds() const;

private:
    GLuint queries_[2] = {0, 0};
};

// The render's speed in --json: samples_per_pixel and rays (each pixel's count, summed),
// and headless, per second of wall_ms, with the GPU's own gpu_ms.
void recordSpeed(course::Session& session, const course::GpuBuffer& rayCounts,
                 unsigned samples, const GpuTimer& timer);
