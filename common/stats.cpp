#include "course/stats.h"

#include <cmath>
#include <cstdio>

namespace course {

std::string jsonEscape(const std::string& text) {
    std::string out;
    for (unsigned char c : text) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += char(c);
        } else if (c < 0x20) {
            char escaped[8];
            std::snprintf(escaped, sizeof escaped, "\\u%04x", c);
            out += escaped;
        } else {
            out += char(c);
        }
    }
    return out;
}

void Stats::put(const std::string& key, std::string jsonValue, double number) {
    for (auto& field : fields_)
        if (field.first == key) {
            field.second = std::move(jsonValue);
            for (auto& n : numbers_)
                if (n.first == key) n.second = number;
            return;
        }
    fields_.emplace_back(key, std::move(jsonValue));
    numbers_.emplace_back(key, number);
}

void Stats::set(const std::string& key, double value) {
    char text[64];
    if (!std::isfinite(value))
        std::snprintf(text, sizeof text, "null");
    else if (value == std::floor(value) && std::fabs(value) < 1e15)
        std::snprintf(text, sizeof text, "%.0f", value);
    else
        std::snprintf(text, sizeof text, "%.6g", value);
    put(key, text, value);
}

void Stats::set(const std::string& key, const std::string& value) {
    put(key, "\"" + jsonEscape(value) + "\"", 0.0);
}

double Stats::number(const std::string& key) const {
    for (const auto& n : numbers_)
        if (n.first == key) return n.second;
    return 0.0;
}

std::string Stats::toJson() const {
    std::string out = "{";
    for (size_t i = 0; i < fields_.size(); ++i)
        out += (i ? ", \"" : "\"") + jsonEscape(fields_[i].first) + "\": " + fields_[i].second;
    return out + "}";
}

GpuTimer::GpuTimer() { glGenQueries(2, queries_); }
GpuTimer::~GpuTimer() { glDeleteQueries(2, queries_); }
void GpuTimer::begin() { glQueryCounter(queries_[0], GL_TIMESTAMP); }
void GpuTimer::end() { glQueryCounter(queries_[1], GL_TIMESTAMP); }

double GpuTimer::milliseconds() const {
    GLuint64 start = 0, end = 0;
    glGetQueryObjectui64v(queries_[0], GL_QUERY_RESULT, &start);
    glGetQueryObjectui64v(queries_[1], GL_QUERY_RESULT, &end);
    return end > start ? double(end - start) * 1e-6 : 0.0;
}

}  // namespace course
