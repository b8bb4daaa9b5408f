// The display's options and keys: exposure and the tone-mapping curve that display.comp
// applies for the window and PNGs (tone_mapping.glsl).
#pragma once
#include <string>

#include "course/cli.h"
#include "course/key_presses.h"
#include "shared.h"  // gpu::PathParameters, TONE_MAP_*

struct DisplayOptions {
    float exposure = 0.0f;         // --exposure EV
    std::string toneMap = "aces";  // --tone-map
};

void declareDisplayOptions(course::CommandLine& cli, DisplayOptions& options);

// TONE_MAP_CLAMP, _REINHARD, _ACES or _FALSE_COLOUR for a --tone-map word.
int toneMapCode(const std::string& name);

// --view: what the image shows (the radiance, or what the camera rays hit), and its
// VIEW_* code (shared.h).
void declareViewOption(course::CommandLine& cli, std::string& view);
int viewCode(const std::string& name);

// Window keys: - and = change the exposure by half a stop, T steps to the next curve.
void adjustDisplay(GLFWwindow* window, course::KeyPresses& keys,
                   gpu::PathParameters& parameters);
