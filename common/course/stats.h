// The one line of statistics --json prints: numbers and strings by name, in the order
// they were first set. Also the GPU timer behind the "gpu_ms" figures.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "course/gl.h"

namespace course {

class Stats {
public:
    void set(const std::string& key, double value);
    void set(const std::string& key, const std::string& value);
    std::string toJson() const;
    double number(const std::string& key) const;  // 0 when unset

private:
    void put(const std::string& key, std::string jsonValue, double number);
    std::vector<std::pair<std::string, std::string>> fields_;
    std::vector<std::pair<std::string, double>> numbers_;
};

std::string jsonEscape(const std::string& text);

// Measures GPU time with two GL_TIMESTAMP queries: the GPU's own clock, read when the
// GPU reaches each point, so CPU time spent issuing calls does not count. (Timestamps
// rather than GL_TIME_ELAPSED: llvmpipe reports nonsense for the latter.)
class GpuTimer {
public:
    GpuTimer();
    ~GpuTimer();
    void begin();
    void end();
    double milliseconds() const;  // waits for the result

private:
    GLuint queries_[2] = {0, 0};
};

}  // namespace course
