#include "scene.h"

#include "course/error.h"

std::vector<std::string> sceneNames() { return {"spheres", "single"}; }

[[noreturn]] static void unknownScene(const std::string& name) {
    std::string names;
    for (const std::string& known : sceneNames()) names += (names.empty() ? "" : ", ") + known;
    course::fail(course::ExitCode::BadUsage,
                 "unknown scene '" + name + "'; the scenes are: " + names);
}

// The numpy reference (python_prototypes/reference/shading.py) lists the same scenes.
// --8<-- [start:scenes]
Scene builtInScene(const std::string& name) {
    // Every scene stands on a light grey floor, the plane y = 0 facing up, and is lit by
    // a point light above, to the right and in front.
    Scene scene{{}, {{{0.0f, 1.0f, 0.0f}, 0.0f, {0.75f, 0.75f, 0.75f}}}, {3.0f, 5.0f, 4.0f}};
    if (name == "spheres") {
        // Four spheres resting on the floor: their shadows fall on it and on each other.
        scene.spheres = {
            {{0.0f, 0.5f, 0.0f}, 0.5f, {0.8f, 0.3f, 0.25f}},
            {{-0.4f, 0.3f, 0.85f}, 0.3f, {0.3f, 0.7f, 0.35f}},
            {{0.62f, 0.35f, 0.65f}, 0.35f, {0.3f, 0.45f, 0.85f}},
            {{0.05f, 0.2f, 1.35f}, 0.2f, {0.9f, 0.75f, 0.3f}},
        };
        return scene;
    }
    if (name == "single") {
        scene.spheres = {{{0.0f, 0.5f, 0.0f}, 0.5f, {0.8f, 0.3f, 0.25f}}};
        return scene;
    }
    unknownScene(name);  // exit code 2, with the list of names
}
// --8<-- [end:scenes]
