// Motion (chapter 27): instances that move while the shutter is open. A blurred picture
// gives each path its own instant (path.comp, instances.glsl) and the top level boxes
// swept over the whole interval; a still, or a frame of the window's animation, places
// the instances at one instant and builds the top level again around them, and twists
// the objects (--twist) with their trees refitted.
#pragma once
#include <string>

#include "course/cli.h"
#include "course/scene_file.h"
#include "course/stats.h"
#include "gpu_scene.h"
#include "refit.h"

struct MotionOptions {
    float instant = kWholeShutter;  // --instant S: a still at S of the shutter's interval
    int animationFrames = 0;        // --animate F: the window plays it, F frames a way
    float twistDegrees = 0.0f;      // --twist DEGREES: at the shutter's closing
};
void declareMotionOptions(course::CommandLine& cli, MotionOptions& options);

class Motion {
public:
    // Exit code 2 for options that do not go together (a twist needs an instant: the
    // blurred picture keeps each object's shape); `window`: the session shows one.
    Motion(GpuScene& gpu, const course::SceneFile& scene, SceneBuffers& buffers,
           const MotionOptions& options, bool window);

    // The instant the picture starts at: --instant's, 0 for a shutter that does not
    // open (a still), else kWholeShutter (blurred over the interval).
    float firstInstant() const;
    // The window's frame, back and forth across the interval: 0, 1/F, ... 1, ... 0.
    float instantOfFrame(int frame) const;
    bool animates() const { return options_.animationFrames > 0; }

    // The scene at the instant (or over the whole shutter): the objects twisted and their
    // trees refitted, the instances placed and their top level built; the GPU's copies
    // written over (their sizes stay the same).
    void show(float instant);
    // --json: instant, frames_shown, twist_degrees, object_sah_cost (the refitted trees,
    // summed over the objects), rebuilt_sah_cost (fresh trees over the same triangles),
    // refit_ms, rebuild_ms, instance_tree_ms (the last top level's build).
    void record(course::Stats& json) const;

private:
    GpuScene& gpu_;
    const course::SceneFile& scene_;
    SceneBuffers& buffers_;
    MotionOptions options_;
    RestPose rest_;
    float shown_ = kWholeShutter;
    int framesShown_ = 0;
    double refitCost_ = 0.0, rebuiltCost_ = 0.0, refitMs_ = 0.0, rebuildMs_ = 0.0;
};
