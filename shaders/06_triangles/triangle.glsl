// Where a ray meets a triangle: the Moller-Trumbore algorithm.

// A triangle's corners, however the scene stores them (scene.glsl's cornersOf).
struct Corners {
    vec3 p0, p1, p2;
};

// --8<-- [start:hit_triangle]
// True when the ray meets the triangle at a distance t with tMin < t < tMax; then
// barycentric = (u, v): the hit point is (1 - u - v) * p0 + u * p1 + v * p2.
// Both sides of the triangle count.
bool hitTriangle(Ray ray, Corners triangle, float tMin, float tMax, out float t,
                 out vec2 barycentric) {
    // BEGIN SOLUTION Moller-Trumbore: solve origin + t * direction = p0 + u * e1 + v * e2
    vec3 edge1 = triangle.p1 - triangle.p0;
    vec3 edge2 = triangle.p2 - triangle.p0;
    // Cramer's rule on the 3x3 system [-direction, edge1, edge2] (t, u, v) = toOrigin,
    // each determinant written as a scalar triple product, sharing two cross products.
    vec3 p = cross(ray.direction, edge2);
    float determinant = dot(edge1, p);
    // Zero: the ray runs parallel to the triangle's plane. Negative: it comes from the
    // back; both sides count, so only the size is tested.
    if (abs(determinant) < 1e-12) return false;
    float inverse = 1.0 / determinant;
    vec3 toOrigin = ray.origin - triangle.p0;
    float u = dot(toOrigin, p) * inverse;
    if (u < 0.0 || u > 1.0) return false;  // outside the edge opposite p1
    vec3 q = cross(toOrigin, edge1);
    float v = dot(ray.direction, q) * inverse;
    if (v < 0.0 || u + v > 1.0) return false;  // outside the other two edges
    t = dot(edge2, q) * inverse;
    barycentric = vec2(u, v);
    return t > tMin && t < tMax;
    // STUB: return false;
    // END SOLUTION
}
// --8<-- [end:hit_triangle]

// --no-normal-flip: keep the normal the corners' order gives, even seen from behind.
uniform bool flipNormals;

// --8<-- [start:triangle_hit]
// What the ray found where it meets the triangle at t.
Hit triangleHit(Ray ray, float t, vec2 barycentric, Corners triangle, vec3 albedo) {
    vec3 edge1 = triangle.p1 - triangle.p0;
    vec3 edge2 = triangle.p2 - triangle.p0;
    // The corners' order decides which way cross() points: counter-clockwise seen from
    // the front. A triangle has no inside, so we turn the normal to face the ray.
    vec3 normal = normalize(cross(edge1, edge2));
    // BEGIN SOLUTION two-sided: the normal faces the side the ray came from
    if (flipNormals && dot(normal, ray.direction) > 0.0) normal = -normal;
    // END SOLUTION
    vec3 position = ray.origin + t * ray.direction;
    return Hit(t, position, normal, albedo, barycentric);
}
// --8<-- [end:triangle_hit]
