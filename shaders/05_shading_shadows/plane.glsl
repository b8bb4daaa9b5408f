// Where a ray meets an infinite plane, such as a floor.

// --8<-- [start:hit_plane]
// True when the ray meets the plane at a distance t with tMin < t < tMax.
bool hitPlane(Ray ray, Plane plane, float tMin, float tMax, out float t) {
    // BEGIN SOLUTION intersect the ray with the plane
    // Along the ray, dot(normal, origin + t * direction) changes by `approach` per
    // unit of t; it must change from dot(normal, origin) to the plane's offset.
    float approach = dot(plane.normal, ray.direction);
    if (abs(approach) < 1e-9) return false;  // parallel: never meets it
    t = (plane.offset - dot(plane.normal, ray.origin)) / approach;
    return t > tMin && t < tMax;
    // STUB: return false;
    // END SOLUTION
}
// --8<-- [end:hit_plane]

// --8<-- [start:plane_hit]
// What the ray found where it meets the plane at t: the same normal everywhere.
Hit planeHit(Ray ray, float t, Plane plane) {
    return Hit(t, ray.origin + t * ray.direction, plane.normal, plane.albedo);
}
// --8<-- [end:plane_hit]
