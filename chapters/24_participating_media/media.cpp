#include "media.h"

#include <string>

#include "course/text_file.h"

// --8<-- [start:media]
void addMedia(const course::SceneFile& scene, gpu::PathParameters& parameters) {
    if (scene.media.size() > MAX_MEDIA)
        course::failAtLine(scene.path, scene.media[MAX_MEDIA].line,
                           "more than " + std::to_string(MAX_MEDIA) +
                               " media: this program's table holds " +
                               std::to_string(MAX_MEDIA));
    for (size_t i = 0; i < scene.media.size(); ++i) {
        const course::SceneMedium& medium = scene.media[i];
        if (medium.kind != course::MediumKind::Homogeneous)
            course::failAtLine(scene.path, medium.line,
                               "medium " + course::inQuotes(medium.name) +
                                   " is a grid: this program renders homogeneous media only; grids "
                                   "come in chapter 25");
        parameters.media[i] = {medium.sigmaA, medium.g, medium.sigmaS, 0.0f};
    }
    parameters.mediumCount = uint32_t(scene.media.size());
    parameters.cameraMedium =
        scene.camera.medium < 0 ? NO_MEDIUM : uint32_t(scene.camera.medium);
}
// --8<-- [end:media]
