// Fuzzes the scene-file parser (common/scene_file.cpp) from memory; a scene that parses
// must also survive a round trip through formatSceneFile (the writer) and parse again.
#include <string>
#include <string_view>

#include "course/error.h"
#include "course/scene_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        course::SceneSupport everything;  // every statement read
        for (course::SceneFeature* feature : {&everything.metals, &everything.glass,
                                              &everything.lens, &everything.textures,
                                              &everything.environment, &everything.media})
            feature->read = true;
        course::SceneFile scene =
            course::parseSceneText(text, "/fuzz/input.scene", {}, everything);
        std::string written = course::formatSceneFile(scene);
        try {
            course::parseSceneText(written, "/fuzz/written.scene", {}, everything);
        } catch (const course::Failure&) {
            __builtin_trap();  // what the writer writes, the reader must read
        }
    } catch (const course::Failure&) {
    }
    return 0;
}
