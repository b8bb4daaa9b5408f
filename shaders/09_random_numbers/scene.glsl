// The scene: a triangle mesh in storage buffers, positions, normals and indices, the
// search for the surface a ray sees, and the question whether anything is in the way.

// --8<-- [start:buffers]
// vec4, not vec3: a std430 vec3 array has a 16-byte stride anyway (shared.h).
layout(std430, binding = POSITIONS_BINDING) readonly buffer Positions {
    vec4 positions[];  // xyz used
};
layout(std430, binding = TRIANGLES_BINDING) readonly buffer Triangles {
    Triangle triangles[];
};
// --8<-- [end:buffers]
// --8<-- [start:normals]
layout(std430, binding = NORMALS_BINDING) readonly buffer Normals {
    vec4 normals[];  // xyz used
};

// A triangle's corner normals, looked up only for hits: tests do not need them.
CornerNormals normalsOf(Triangle triangle) {
    return CornerNormals(normals[triangle.cornerNormals.x].xyz,
                         normals[triangle.cornerNormals.y].xyz,
                         normals[triangle.cornerNormals.z].xyz);
}
// --8<-- [end:normals]

// The albedo of each material: the share of red, green and blue light it reflects.
const vec3 ALBEDO[2] = vec3[2](vec3(0.9, 0.55, 0.25),  // MATERIAL_MESH: terracotta
                               vec3(0.7, 0.7, 0.7));   // MATERIAL_FLOOR: light grey

// --8<-- [start:corners]
// A triangle's corners: three lookups in the positions buffer through its indices.
Corners cornersOf(Triangle triangle) {
    return Corners(positions[triangle.corners.x].xyz, positions[triangle.corners.y].xyz,
                   positions[triangle.corners.z].xyz);
}
// --8<-- [end:corners]

// --8<-- [start:nearest]
// The nearest surface along the ray, between tMin and tMax.
bool nearestHit(Ray ray, float tMin, float tMax, out Hit hit) {
    bool found = false;
    hit.t = tMax;  // only hits nearer than this count; it shrinks with each hit found
    for (int i = 0; i < triangles.length(); ++i) {
        Corners corners = cornersOf(triangles[i]);
        float t;
        vec2 barycentric;
        if (hitTriangle(ray, corners, tMin, hit.t, t, barycentric)) {
            hit = triangleHit(ray, t, barycentric, corners, normalsOf(triangles[i]),
                              ALBEDO[triangles[i].material]);
            found = true;
        }
    }
    return found;
}
// --8<-- [end:nearest]

// --8<-- [start:any_hit]
// Is anything in the way between tMin and tMax? For a shadow ray any hit will do, so
// the search stops at the first one: what was a bug for camera rays is right here.
bool anyHit(Ray ray, float tMin, float tMax) {
    float t;
    vec2 barycentric;
    for (int i = 0; i < triangles.length(); ++i)
        if (hitTriangle(ray, cornersOf(triangles[i]), tMin, tMax, t, barycentric))
            return true;
    return false;
}
// --8<-- [end:any_hit]
