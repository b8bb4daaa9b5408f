#include "checked_dispatch.h"

#include <algorithm>
#include <cstdint>
#include <utility>  // std::move

#include "course/error.h"
#include "course/gl.h"
#include "course/log.h"
#include "shared.h"  // CUT_SHORT_BINDING

CheckedDispatch::CheckedDispatch(std::vector<const course::GpuBuffer*> changed, int samples,
                                 bool check, std::string sceneFile)
    : changed_(std::move(changed)), cutShort_(sizeof(uint32_t)), samples_(samples),
      check_(check), sceneFile_(std::move(sceneFile)) {
    if (check_)
        for (const course::GpuBuffer* buffer : changed_) copies_.emplace_back(buffer->bytes());
    // An atomic counter buffer, which path.comp can only add to (atomicCounterIncrement).
    glBindBufferBase(GL_ATOMIC_COUNTER_BUFFER, CUT_SHORT_BINDING, cutShort_.id());
}

// --8<-- [start:copies]
// A copy from buffer to buffer stays on the GPU: no trip through the CPU's memory.
static void copyBuffer(const course::GpuBuffer& from, const course::GpuBuffer& to) {
    glBindBuffer(GL_COPY_READ_BUFFER, from.id());
    glBindBuffer(GL_COPY_WRITE_BUFFER, to.id());
    glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, 0, 0,
                        static_cast<GLsizeiptr>(from.bytes()));
}
// Both wait, once for all their copies, for what the shaders wrote before them.
void CheckedDispatch::keep() {
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    for (size_t i = 0; i < changed_.size(); ++i) copyBuffer(*changed_[i], copies_[i]);
}
void CheckedDispatch::putBack() {
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    for (size_t i = 0; i < changed_.size(); ++i) copyBuffer(copies_[i], *changed_[i]);
}
// --8<-- [end:copies]

// --8<-- [start:add]
int CheckedDispatch::add(int wanted, const std::function<void(int)>& dispatch) {
    for (;;) {
        const int n = std::min(wanted, samples_);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);  // it reads what the last wrote
        if (!check_) {
            dispatch(n);
            return n;
        }
        keep();
        const uint32_t none = 0;
        cutShort_.write(&none, sizeof none);
        dispatch(n);
        uint32_t cut = 0;
        cutShort_.read(&cut, sizeof cut);  // waits for the dispatch to finish
        if (cut == 0) return n;
        if (n == 1)
            course::fail(course::ExitCode::GlProblem,
                         sceneFile_ + ": this GL's loop limit cut " + std::to_string(cut) +
                             " invocations short even at one sample a dispatch: the "
                             "paths are too long for it. A lower --depth, or a GL without "
                             "the limit renders the scene (a GPU; Mesa 25's llvmpipe has none).");
        // The samples it added are wrong somewhere: back to before it, with half as many.
        putBack();
        samples_ = std::max(1, n / 2);
        ++redone_;
        course::logInfo("the GL's loop limit cut " + std::to_string(cut) +
                        " invocations short: the dispatch again, at " +
                        std::to_string(samples_) + " samples");
    }
}
// --8<-- [end:add]

void CheckedDispatch::record(course::Stats& stats, int spp) const {
    stats.set("samples_per_dispatch", std::min(samples_, spp));
    stats.set("dispatches_redone", redone_);
}
