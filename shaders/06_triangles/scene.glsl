// The scene: spheres and triangles in storage buffers, the search for the surface a
// ray sees, and the question whether anything at all is in the way.

layout(std430, binding = SPHERES_BINDING) readonly buffer Spheres { Sphere spheres[]; };
layout(std430, binding = TRIANGLES_BINDING) readonly buffer Triangles {
    Triangle triangles[];
};

// A triangle's corners: the xyz of the stored vec4s (shared.h says why vec4).
Corners cornersOf(Triangle triangle) {
    return Corners(triangle.p0.xyz, triangle.p1.xyz, triangle.p2.xyz);
}

// --8<-- [start:nearest]
// The nearest surface along the ray, between tMin and tMax.
bool nearestHit(Ray ray, float tMin, float tMax, out Hit hit) {
    bool found = false;
    hit.t = tMax;  // only hits nearer than this count; it shrinks with each hit found
    for (int i = 0; i < spheres.length(); ++i) {
        float t;
        // Searching only up to the nearest hit so far: a sphere behind it cannot win.
        if (hitSphere(ray, spheres[i], tMin, hit.t, t)) {
            hit = sphereHit(ray, t, spheres[i]);
            found = true;
        }
    }
    for (int i = 0; i < triangles.length(); ++i) {
        Corners corners = cornersOf(triangles[i]);
        float t;
        vec2 barycentric;
        if (hitTriangle(ray, corners, tMin, hit.t, t, barycentric)) {
            hit = triangleHit(ray, t, barycentric, corners, triangles[i].albedo.rgb);
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
    for (int i = 0; i < spheres.length(); ++i)
        if (hitSphere(ray, spheres[i], tMin, tMax, t)) return true;
    for (int i = 0; i < triangles.length(); ++i)
        if (hitTriangle(ray, cornersOf(triangles[i]), tMin, tMax, t, barycentric))
            return true;
    return false;
}
// --8<-- [end:any_hit]
