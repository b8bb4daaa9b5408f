// A long render's progress, for a person watching a terminal: samples done of how
// many, samples per second and the time left, on one line of stderr rewritten in place
// (Session::timeRender shows it for the chapters that give it their sample counter).
// Quiet when stderr is not a terminal (files, pipes, the tests, the grader) and for
// renders that end within a couple of seconds; stdout (--json, the image's path) is
// never touched.
#pragma once

namespace course {

class RenderProgress {
public:
    // `samplesDone` is the chapter's own counter, read on the main thread only.
    RenderProgress(const unsigned& samplesDone, int samplesWanted);
    ~RenderProgress();  // the line is cleared
    RenderProgress(const RenderProgress&) = delete;
    RenderProgress& operator=(const RenderProgress&) = delete;

    // Called on the main thread after each step of GPU work is queued (gpuStepQueued):
    // redraws the line at most a few times a second.
    static void stepTaken();
};

}  // namespace course
