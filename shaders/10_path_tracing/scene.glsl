// The scene: spheres, quads and triangles in storage buffers, each with a material.
// Every ray tests every shape (chapter 12's BVH does better); the Cornell scenes have a
// few dozen shapes, the gems ~150.

layout(std430, binding = SPHERES_BINDING) readonly buffer Spheres { Sphere spheres[]; };
layout(std430, binding = QUADS_BINDING) readonly buffer Quads { Quad quads[]; };
layout(std430, binding = TRIANGLES_BINDING) readonly buffer Triangles {
    Triangle triangles[];
};
layout(std430, binding = MATERIALS_BINDING) readonly buffer Materials {
    Material materials[];
};

// What a ray found.
struct Hit {
    float t;
    vec3 position;
    vec3 normal;     // unit length, on the shape's front side (outside, for a sphere)
    bool front;      // did the ray arrive at the front?
    uint material;
};

// The nearer root of |origin + t direction - centre|^2 = r^2 inside (tMin, tMax).
bool hitSphere(Ray ray, Sphere sphere, float tMin, float tMax, out float t) {
    vec3 toOrigin = ray.origin - sphere.center;
    float halfB = dot(toOrigin, ray.direction);
    float c = dot(toOrigin, toOrigin) - sphere.radius * sphere.radius;
    float discriminant = halfB * halfB - c;
    if (discriminant < 0.0) return false;
    float root = sqrt(discriminant);
    // -b - sqrt(...) loses digits when b is large and negative: q / a is exact there.
    float q = -halfB - (halfB >= 0.0 ? root : -root);
    if (q == 0.0) return false;  // the origin on the sphere, the ray along its tangent
    float t1 = q, t2 = c / q;
    t = min(t1, t2);
    if (t <= tMin) t = max(t1, t2);
    return t > tMin && t < tMax;
}

// Where the ray meets the quad's plane, if the point is inside the parallelogram.
bool hitQuad(Ray ray, Quad quad, float tMin, float tMax, out float t) {
    vec3 normal = cross(quad.edge1, quad.edge2);
    float facing = dot(normal, ray.direction);
    if (abs(facing) < 1e-20) return false;  // parallel to the plane
    t = dot(normal, quad.origin - ray.origin) / facing;
    if (!(t > tMin && t < tMax)) return false;
    // The point's coordinates along the two edges, each in [0, 1] inside: solve
    // p = origin + a edge1 + b edge2 with the dual vectors of the edges.
    vec3 p = ray.origin + t * ray.direction - quad.origin;
    vec3 w = normal / dot(normal, normal);
    float a = dot(w, cross(p, quad.edge2));
    float b = dot(w, cross(quad.edge1, p));
    return a >= 0.0 && a <= 1.0 && b >= 0.0 && b <= 1.0;
}

// Moller-Trumbore, both sides (chapter 06).
bool hitTriangle(Ray ray, Triangle triangle, float tMin, float tMax, out float t) {
    vec3 edge1 = triangle.p1 - triangle.p0;
    vec3 edge2 = triangle.p2 - triangle.p0;
    vec3 p = cross(ray.direction, edge2);
    float determinant = dot(edge1, p);
    if (abs(determinant) < 1e-20) return false;
    float inverse = 1.0 / determinant;
    vec3 toOrigin = ray.origin - triangle.p0;
    float u = dot(toOrigin, p) * inverse;
    if (u < 0.0 || u > 1.0) return false;
    vec3 q = cross(toOrigin, edge1);
    float v = dot(ray.direction, q) * inverse;
    if (v < 0.0 || u + v > 1.0) return false;
    t = dot(edge2, q) * inverse;
    return t > tMin && t < tMax;
}

// Fills in a hit from the shape's front normal and material.
Hit makeHit(Ray ray, float t, vec3 frontNormal, uint material) {
    vec3 normal = normalize(frontNormal);
    return Hit(t, ray.origin + t * ray.direction, normal,
               dot(normal, ray.direction) < 0.0, material);
}

// --8<-- [start:nearest]
// The nearest surface along the ray, between tMin and tMax.
bool nearestHit(Ray ray, float tMin, float tMax, out Hit hit) {
    int kind = -1, index = 0;
    float t;
    for (int i = 0; i < spheres.length(); ++i)
        if (hitSphere(ray, spheres[i], tMin, tMax, t)) {
            tMax = t; kind = SHAPE_SPHERE; index = i;
        }
    for (int i = 0; i < quads.length(); ++i)
        if (hitQuad(ray, quads[i], tMin, tMax, t)) {
            tMax = t; kind = SHAPE_QUAD; index = i;
        }
    for (int i = 0; i < triangles.length(); ++i)
        if (hitTriangle(ray, triangles[i], tMin, tMax, t)) {
            tMax = t; kind = SHAPE_TRIANGLE; index = i;
        }
    // Normals only for the one shape that was hit.
    if (kind == SHAPE_SPHERE) {
        Sphere s = spheres[index];
        hit = makeHit(ray, tMax, ray.origin + tMax * ray.direction - s.center, s.material);
    } else if (kind == SHAPE_QUAD) {
        Quad q = quads[index];
        hit = makeHit(ray, tMax, cross(q.edge1, q.edge2), q.material);
    } else if (kind == SHAPE_TRIANGLE) {
        Triangle tr = triangles[index];
        hit = makeHit(ray, tMax, cross(tr.p1 - tr.p0, tr.p2 - tr.p0), tr.material);
    }
    return kind >= 0;
}
// --8<-- [end:nearest]
