// The scene's participating media (course/scene_file.h's `medium` lines) as the
// shaders read them: a table of at most MAX_MEDIA in the PathParameters block, and
// the medium around the camera.
#pragma once
#include "course/scene_file.h"
#include "shared.h"

// Fills parameters.media, mediumCount and cameraMedium; more media than MAX_MEDIA is
// exit code 3 at the first line past it.
void addMedia(const course::SceneFile& scene, gpu::PathParameters& parameters);
