#include "gpu_timer.h"

double GpuTimer::milliseconds() const {
    GLuint64 start = 0, stop = 0;
    glGetQueryObjectui64v(queries_[0], GL_QUERY_RESULT, &start);  // waits for it
    glGetQueryObjectui64v(queries_[1], GL_QUERY_RESULT, &stop);
    return double(stop - start) * 1e-6;
}
