// Trying the ways to make a GL context in order, best first: the first that works
// wins. One that says its GL is too old does not end the search (a later device may be
// a newer GPU); only when none works does the search end, with "too old" if one said so.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "course/gl_context.h"

namespace course {

struct ContextCandidate {
    std::string description;  // "egl device 1 (NVIDIA GeForce ...)"
    // A current context, or nullptr with `reason` set; throws GlTooOld when the GL there
    // is older than the chapter needs.
    std::function<std::unique_ptr<GlContext>(std::string& reason)> attempt;
};

// The first candidate's context that works. None: throws the first GlTooOld if any was
// thrown, else returns nullptr with every reason in `reasons`, one a line.
std::unique_ptr<GlContext> firstWorkingContext(const std::vector<ContextCandidate>& candidates,
                                               std::string& reasons);

}  // namespace course
