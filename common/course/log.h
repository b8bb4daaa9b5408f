// Two kinds of messages: progress for --verbose, and warnings that always show.
// Both go to stderr so that stdout stays clean for --json.
#pragma once
#include <cstdio>
#include <string>

namespace course {

inline bool& verboseLogging() {
    static bool enabled = false;
    return enabled;
}

inline void logInfo(const std::string& message) {
    if (verboseLogging()) std::fprintf(stderr, "[course] %s\n", message.c_str());
}

inline void logWarning(const std::string& message) {
    std::fprintf(stderr, "warning: %s\n", message.c_str());
}

}  // namespace course
