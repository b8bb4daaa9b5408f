#include "gpu_timer.h"

#include <numeric>
#include <vector>

double GpuTimer::milliseconds() const {
    GLuint64 start = 0, stop = 0;
    glGetQueryObjectui64v(queries_[0], GL_QUERY_RESULT, &start);  // waits for it
    glGetQueryObjectui64v(queries_[1], GL_QUERY_RESULT, &stop);
    return double(stop - start) * 1e-6;
}

void recordSpeed(course::Session& session, const course::GpuBuffer& rayCounts,
                 unsigned samples, const GpuTimer& timer) {
    std::vector<uint32_t> counts = rayCounts.readAll<uint32_t>();
    double rays = std::accumulate(counts.begin(), counts.end(), 0.0);
    session.stats().set("samples_per_pixel", double(samples));
    session.stats().set("rays", rays);
    if (session.isWindow()) return;
    double seconds = session.stats().number("wall_ms") / 1000.0;
    const course::Options& options = session.options();
    double all = double(options.width) * options.height * samples;
    session.stats().set("samples_per_second", all / seconds);
    session.stats().set("rays_per_second", rays / seconds);
    session.stats().set("gpu_ms", timer.milliseconds());
}
