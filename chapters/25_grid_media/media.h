// The scene's participating media (course/scene_file.h's `medium` lines) as the
// shaders read them: a table of at most MAX_MEDIA in the PathParameters block, the
// medium around the camera, and every grid's densities for the densities texture.
#pragma once
#include <vector>

#include "course/scene_file.h"
#include "shared.h"

// Fills parameters.media, mediumCount and cameraMedium, and returns the grids'
// densities one after another (Medium::firstValue says where each starts), padded to
// whole texels of four. More media than MAX_MEDIA, or a grid too dense for this
// program's tracking steps, is exit code 3 at the medium's line.
std::vector<float> addMedia(const course::SceneFile& scene, gpu::PathParameters& parameters);

// The most steps delta and ratio tracking may take in one bounce: the free flight's and
// those of a shadow ray's `segments` (0 without grids), for the loop budget.
size_t trackingSteps(const course::SceneFile& scene, size_t segments);
