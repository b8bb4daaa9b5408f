#include "course/context_search.h"

#include <optional>

#include "course/log.h"

namespace course {

std::unique_ptr<GlContext> firstWorkingContext(const std::vector<ContextCandidate>& candidates,
                                               std::string& reasons) {
    std::optional<GlTooOld> tooOld;
    for (const ContextCandidate& candidate : candidates) {
        std::string reason;
        try {
            if (auto context = candidate.attempt(reason)) return context;
        } catch (const GlTooOld& old) {
            if (!tooOld) tooOld = old;
            reason = candidate.description + ": " + old.what();
        }
        logInfo(reason);
        reasons += "\n  " + reason;
    }
    if (tooOld) throw *tooOld;
    return nullptr;
}

}  // namespace course
