// Where a ray meets a sphere, by geometry: first the point of the ray closest to the
// centre, then Pythagoras.

// --8<-- [start:hit_sphere]
// True when the ray meets the sphere at a distance t with tMin < t < tMax; t is then
// the nearer such meeting point. The ray's direction must be of unit length.
bool hitSphere(Ray ray, Sphere sphere, float tMin, float tMax, out float t) {
    // 1. Project the centre onto the ray: tClosest is where the ray passes closest.
    vec3 toCenter = sphere.center - ray.origin;
    float tClosest = dot(toCenter, ray.direction);
    // 2. How close it passes: the vector from that point to the centre. (Computed as a
    //    vector, not as |toCenter|^2 - tClosest^2, which cancels badly when far away.)
    vec3 closestToCenter = toCenter - tClosest * ray.direction;
    float missBySquared = dot(closestToCenter, closestToCenter);
    float radiusSquared = sphere.radius * sphere.radius;
    if (missBySquared > radiusSquared) return false;  // passes outside the sphere
    // 3. Pythagoras: the ray is inside the sphere for halfChord either side of it.
    float halfChord = sqrt(radiusSquared - missBySquared);
    t = tClosest - halfChord;                      // where the ray enters ...
    if (t <= tMin) t = tClosest + halfChord;       // ... or leaves, if it starts inside
    return t > tMin && t < tMax;
}
// --8<-- [end:hit_sphere]

// --8<-- [start:sphere_hit]
// What the ray found where it meets the sphere at t.
Hit sphereHit(Ray ray, float t, Sphere sphere) {
    vec3 position = ray.origin + t * ray.direction;
    // A sphere's normal points from its centre through the surface point; dividing by
    // the radius makes it a unit vector.
    return Hit(t, position, (position - sphere.center) / sphere.radius, sphere.albedo);
}
// --8<-- [end:sphere_hit]
