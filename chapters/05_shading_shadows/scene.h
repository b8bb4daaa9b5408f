// The built-in scenes of this chapter, chosen with --scene NAME.
#pragma once
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "shared.h"  // gpu::Sphere and gpu::Plane, laid out as the shader reads them

struct Scene {
    std::vector<gpu::Sphere> spheres;
    std::vector<gpu::Plane> planes;
    glm::vec3 lightPosition;  // a point light
};

// The names --scene accepts, the default first.
std::vector<std::string> sceneNames();

// The scene called `name`; an unknown name is exit code 2, with the list of names.
Scene builtInScene(const std::string& name);
