// The scene around a mesh, made from the mesh's bounds alone, so that any OBJ file
// renders without settings: a camera that frames it, a floor under it, a light above.
// python_prototypes/reference/mesh_scene.py builds the same scene for the checks.
#pragma once
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "camera.h"
#include "obj_loader.h"
#include "shared.h"  // gpu::Triangle, laid out as the shader reads it

struct Scene {
    std::vector<glm::vec4> positions;      // the mesh's, then the floor's 4 corners; w unused
    std::vector<glm::vec4> normals;        // the mesh's, then the floor's one; w unused
    std::vector<gpu::Triangle> triangles;  // the mesh's, then the floor's 2
    Camera camera;                         // frames the mesh's bounding sphere
    glm::vec3 lightPosition;               // a point light above, right and in front
    float shadowOffset;                    // SHADOW_OFFSET * (1 + radius)
    float radius;                          // of the mesh's bounding sphere
};

// The mesh with its floor, camera and light for a width x height picture. The mesh
// must have normals at every corner (normals.h makes them for files without). A mesh
// with no extent (every vertex at one point) cannot be framed: exit code 3, naming `path`.
Scene sceneAround(const Mesh& mesh, const std::string& path, int width, int height);
