#include "scene.h"

#include "course/error.h"

std::vector<std::string> sceneNames() { return {"spheres", "single"}; }

[[noreturn]] static void unknownScene(const std::string& name) {
    std::string names;
    for (const std::string& known : sceneNames()) names += (names.empty() ? "" : ", ") + known;
    course::fail(course::ExitCode::BadUsage,
                 "unknown scene '" + name + "'; the scenes are: " + names);
}

// The numpy reference (python_prototypes/reference/spheres.py) lists the same scenes.
// --8<-- [start:scenes]
Scene builtInScene(const std::string& name) {
    Scene scene;
    if (name == "spheres") {
        // Four spheres resting on y = 0, the big one listed first. From the camera, the
        // three smaller ones in front overlap it: the nearest hit must win.
        scene.spheres = {
            {{0.0f, 0.5f, 0.0f}, 0.5f},
            {{-0.4f, 0.3f, 0.85f}, 0.3f},
            {{0.62f, 0.35f, 0.65f}, 0.35f},
            {{0.05f, 0.2f, 1.35f}, 0.2f},
        };
        return scene;
    }
    if (name == "single") {
        scene.spheres = {{{0.0f, 0.5f, 0.0f}, 0.5f}};
        return scene;
    }
    unknownScene(name);  // exit code 2, with the list of names
}
// --8<-- [end:scenes]
