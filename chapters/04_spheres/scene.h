// The built-in scenes of this chapter, chosen with --scene NAME.
#pragma once
#include <string>
#include <vector>

#include "shared.h"  // gpu::Sphere, laid out as the shader reads it

struct Scene {
    std::vector<gpu::Sphere> spheres;
};

// The names --scene accepts, the default first.
std::vector<std::string> sceneNames();

// The scene called `name`; an unknown name is exit code 2, with the list of names.
Scene builtInScene(const std::string& name);
