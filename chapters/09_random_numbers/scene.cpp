#include "scene.h"

#include <algorithm>
#include <cmath>

#include "course/error.h"

namespace {

// The lens of camera_rays.py: 35 mm focal length on a 36 mm wide sensor.
constexpr float kFocalLength = 0.035f;
constexpr float kSensorWidth = 0.036f;
const glm::vec3 kLook(0.0f, -0.35f, -1.0f);  // from the front, a little from above
const glm::vec3 kLightOffset(2.0f, 4.0f, 3.0f);  // in radii from the centre: right, up, front
constexpr float kFloorHalfSize = 20.0f;          // in radii

struct Bounds {
    glm::vec3 lo, hi;
    glm::vec3 center() const { return 0.5f * (lo + hi); }
    float radius() const { return 0.5f * glm::length(hi - lo); }  // of the bounding sphere
};

Bounds boundsOf(const std::vector<glm::vec3>& positions) {
    Bounds bounds{positions.front(), positions.front()};
    for (const glm::vec3& p : positions) {
        bounds.lo = glm::min(bounds.lo, p);
        bounds.hi = glm::max(bounds.hi, p);
    }
    return bounds;
}

// --8<-- [start:framing]
// A camera that looks at the sphere around the mesh's bounding box from the front and
// a little above, from just far enough away that the whole sphere is in the picture.
Camera frameSphere(glm::vec3 center, float radius, int width, int height) {
    // The narrower of the picture's two angles of view decides (for a 4:3 picture, the
    // vertical one): halfFov is the angle between the view's centre and its edge.
    float sensorHeight = kSensorWidth * float(height) / float(width);
    float halfFov = std::atan(std::min(kSensorWidth, sensorHeight) / 2.0f / kFocalLength);
    // A line from the eye that grazes the sphere makes a right angle with the radius
    // at the point it touches: sin(angle) = radius / distance. The sphere just fits
    // when that angle is halfFov.
    float distance = radius / std::sin(halfFov);
    glm::vec3 look = glm::normalize(kLook);
    return makeCamera(center - look * distance, look, glm::vec3(0.0f, 1.0f, 0.0f),
                      kFocalLength, kSensorWidth);
}
// --8<-- [end:framing]

}  // namespace

// --8<-- [start:scene]
Scene sceneAround(const Mesh& mesh, const std::string& path, int width, int height) {
    const Bounds bounds = boundsOf(mesh.positions);
    const glm::vec3 center = bounds.center();
    const float radius = bounds.radius();
    if (!(radius > 0.0f) || !std::isfinite(radius))
        course::fail(course::ExitCode::BadInput,
                     path + ":0: cannot frame the mesh: its bounding box has size " +
                         std::to_string(2.0f * radius));

    Scene scene;
    scene.camera = frameSphere(center, radius, width, height);
    scene.lightPosition = center + radius * kLightOffset;
    scene.shadowOffset = float(SHADOW_OFFSET) * (1.0f + radius);
    scene.radius = radius;

    // The mesh: glm::vec4(p, 1) because the shader's array has a 16-byte stride, and
    // the same for the normals.
    for (const glm::vec3& p : mesh.positions) scene.positions.push_back(glm::vec4(p, 1.0f));
    for (const glm::vec3& n : mesh.normals) scene.normals.push_back(glm::vec4(n, 0.0f));
    const std::vector<uint32_t>& index = mesh.positionIndices;
    const std::vector<uint32_t>& normal = mesh.normalIndices;
    for (size_t i = 0; i < index.size(); i += 3)
        scene.triangles.push_back({{index[i], index[i + 1], index[i + 2]}, MATERIAL_MESH,
                                   {normal[i], normal[i + 1], normal[i + 2]}, 0});

    // The floor: a square 40 radii wide in the plane under the mesh, two triangles.
    const float half = kFloorHalfSize * radius, y = bounds.lo.y;
    const uint32_t first = uint32_t(scene.positions.size());
    for (glm::vec2 corner : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1),
                             glm::vec2(-1, 1)})
        scene.positions.push_back(
            glm::vec4(center.x + corner.x * half, y, center.z + corner.y * half, 1.0f));
    // Its corners' normals are its own, so it stays flat. As wound (chapter 06), that
    // normal points down; the shader turns it, with the flat one, to face the ray.
    const uint32_t down = uint32_t(scene.normals.size());
    scene.normals.push_back(glm::vec4(0.0f, -1.0f, 0.0f, 0.0f));
    scene.triangles.push_back({{first, first + 1, first + 2}, MATERIAL_FLOOR,
                               {down, down, down}, 0});
    scene.triangles.push_back({{first, first + 2, first + 3}, MATERIAL_FLOOR,
                               {down, down, down}, 0});
    return scene;
}
// --8<-- [end:scene]
