// Where a ray meets a triangle: the Moller-Trumbore algorithm.

// A triangle's corners, once looked up through its indices (cornersOf, below).
struct Corners {
    vec3 p0, p1, p2;
};

// The normals at a triangle's corners, in the same order; not necessarily unit length.
struct CornerNormals {
    vec3 n0, n1, n2;
};

// --8<-- [start:hit_triangle]
// True when the ray meets the triangle at a distance t with tMin < t < tMax; then
// barycentric = (u, v): the hit point is (1 - u - v) * p0 + u * p1 + v * p2.
// Both sides of the triangle count.
bool hitTriangle(Ray ray, Corners triangle, float tMin, float tMax, out float t,
                 out vec2 barycentric) {
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
}
// --8<-- [end:hit_triangle]

// --8<-- [start:smooth_normal]
// The normal at the hit point of a smooth surface that the triangle stands in for:
// the corners' normals blended with the weights that give the hit point itself,
// (1 - u - v) * p0 + u * p1 + v * p2 (Phong's normal interpolation).
vec3 smoothNormal(CornerNormals normals, vec2 barycentric, vec3 flatNormal) {
    float u = barycentric.x, v = barycentric.y;
    vec3 blended = (1.0 - u - v) * normals.n0 + u * normals.n1 + v * normals.n2;
    // Corner normals that cancel out (a sheet folded back on itself) leave no
    // direction: keep the flat one.
    return length(blended) > 1e-12 ? normalize(blended) : flatNormal;
}
// --8<-- [end:smooth_normal]

// --8<-- [start:corners]
// A triangle's corners and their normals, looked up through its indices.
Corners cornersOf(Triangle triangle) {
    return Corners(positionAt(triangle.corners.x), positionAt(triangle.corners.y),
                   positionAt(triangle.corners.z));
}
CornerNormals normalsOf(Triangle triangle) {
    return CornerNormals(normals[triangle.cornerNormals.x].xyz,
                         normals[triangle.cornerNormals.y].xyz,
                         normals[triangle.cornerNormals.z].xyz);
}
// --8<-- [end:corners]

// --8<-- [start:triangle_uv]
// The texture coordinates at the hit point: the corners' vt blended with the same
// weights as the normals.
vec2 triangleUv(Triangle triangle, vec2 barycentric) {
    vec3 weights = vec3(1.0 - barycentric.x - barycentric.y, barycentric);
    return weights.x * uvs[triangle.cornerUvs.x] + weights.y * uvs[triangle.cornerUvs.y]
         + weights.z * uvs[triangle.cornerUvs.z];
}
// --8<-- [end:triangle_uv]

// --8<-- [start:triangle_hit]
// What the ray found where it meets the triangle at t. The flat triangle's own normal
// says which side the ray is on; the corners' normals, blended, are the normal to
// shade with (chapter 08), on the same side: a smooth teapot, not 6 320 facets.
Hit triangleHit(Ray ray, float t, vec2 barycentric, Triangle triangle) {
    Corners corners = cornersOf(triangle);
    // cross() points to the side from which the corners run counter-clockwise.
    vec3 geometricNormal =
        normalize(cross(corners.p1 - corners.p0, corners.p2 - corners.p0));
    vec3 normal = smoothNormal(normalsOf(triangle), barycentric, geometricNormal);
    return Hit(t, ray.origin + t * ray.direction, normal, geometricNormal,
               dot(geometricNormal, ray.direction) < 0.0, triangle.material,
               triangle.emitter, triangleUv(triangle, barycentric));
}
// --8<-- [end:triangle_hit]
