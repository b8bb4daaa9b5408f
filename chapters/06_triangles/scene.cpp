#include "scene.h"

#include "course/error.h"

std::vector<std::string> sceneNames() { return {"spheres", "single", "pyramid"}; }

[[noreturn]] static void unknownScene(const std::string& name) {
    std::string names;
    for (const std::string& known : sceneNames()) names += (names.empty() ? "" : ", ") + known;
    course::fail(course::ExitCode::BadUsage,
                 "unknown scene '" + name + "'; the scenes are: " + names);
}

// --8<-- [start:mesh]
// glm::vec4(v, 1): the shader reads only xyz (rgb), the fourth float is filler.
static gpu::Triangle triangle(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 albedo) {
    return {glm::vec4(a, 1), glm::vec4(b, 1), glm::vec4(c, 1), glm::vec4(albedo, 1)};
}

// A square floor at y = 0, two triangles. The corners are listed in the order that
// reads naturally, x first, then z; seen from above that is clockwise, so the normals
// cross(edge1, edge2) of both triangles point down, into the ground.
static void addFloor(std::vector<gpu::Triangle>& triangles, float halfSize, glm::vec3 albedo) {
    glm::vec3 a(-halfSize, 0, -halfSize), b(halfSize, 0, -halfSize);
    glm::vec3 c(halfSize, 0, halfSize), d(-halfSize, 0, halfSize);
    triangles.push_back(triangle(a, b, c, albedo));
    triangles.push_back(triangle(a, c, d, albedo));
}

// A four-sided pyramid standing on the floor, turned 45 degrees so that it shows the
// camera two differently lit faces, and without its (hidden) base: four triangles,
// each wound counter-clockwise seen from outside, so that its normals point out.
static void addPyramid(std::vector<gpu::Triangle>& triangles, glm::vec3 baseCenter,
                       float radius, float height, glm::vec3 albedo) {
    glm::vec3 apex = baseCenter + glm::vec3(0, height, 0);
    glm::vec3 corners[4] = {baseCenter + glm::vec3(0, 0, radius),
                            baseCenter + glm::vec3(radius, 0, 0),
                            baseCenter + glm::vec3(0, 0, -radius),
                            baseCenter + glm::vec3(-radius, 0, 0)};
    for (int i = 0; i < 4; ++i)
        triangles.push_back(triangle(corners[i], corners[(i + 1) % 4], apex, albedo));
}
// --8<-- [end:mesh]

// The numpy reference (python_prototypes/reference/triangles.py) lists the same scenes.
// --8<-- [start:scenes]
Scene builtInScene(const std::string& name) {
    // Every scene stands on a light grey floor, a square 40 m wide made of two triangles,
    // and is lit by a point light above, to the right and in front.
    Scene scene{{}, {}, {3.0f, 5.0f, 4.0f}};
    addFloor(scene.triangles, 20.0f, {0.75f, 0.75f, 0.75f});
    if (name == "spheres") {
        // Four spheres resting on the floor, and a pyramid behind them on the left.
        scene.spheres = {
            {{0.0f, 0.5f, 0.0f}, 0.5f, {0.8f, 0.3f, 0.25f}},
            {{-0.4f, 0.3f, 0.85f}, 0.3f, {0.3f, 0.7f, 0.35f}},
            {{0.62f, 0.35f, 0.65f}, 0.35f, {0.3f, 0.45f, 0.85f}},
            {{0.05f, 0.2f, 1.35f}, 0.2f, {0.9f, 0.75f, 0.3f}},
        };
        addPyramid(scene.triangles, {-1.1f, 0.0f, -0.6f}, 0.5f, 0.9f, {0.85f, 0.8f, 0.7f});
        return scene;
    }
    if (name == "single") {
        scene.spheres = {{{0.0f, 0.5f, 0.0f}, 0.5f, {0.8f, 0.3f, 0.25f}}};
        return scene;
    }
    if (name == "pyramid") {
        addPyramid(scene.triangles, {0.0f, 0.0f, 0.0f}, 0.8f, 1.0f, {0.85f, 0.8f, 0.7f});
        return scene;
    }
    unknownScene(name);  // exit code 2, with the list of names
}
// --8<-- [end:scenes]
