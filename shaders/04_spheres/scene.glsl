// The scene: spheres in a storage buffer, and the search for the one a ray sees.

layout(std430, binding = SPHERES_BINDING) readonly buffer Spheres { Sphere spheres[]; };

// --first-hit: take the first sphere in the list that the ray meets, not the nearest.
// The classic bug, kept behind a switch so the book can show what it looks like.
uniform bool firstHitOnly;

// --8<-- [start:nearest]
// The nearest surface along the ray, between tMin and tMax.
bool nearestHit(Ray ray, float tMin, float tMax, out Hit hit) {
    bool found = false;
    hit.t = tMax;  // only hits nearer than this count; it shrinks with each hit found
    for (int i = 0; i < spheres.length(); ++i) {
        float t;
        // BEGIN SOLUTION keep the nearest hit
        // Searching only up to the nearest hit so far: a sphere behind it cannot win.
        if (hitSphere(ray, spheres[i], tMin, hit.t, t)) {
            hit = sphereHit(ray, t, spheres[i]);
            found = true;
            if (firstHitOnly) break;  // the bug: a later sphere might be nearer
        }
        // END SOLUTION
    }
    return found;
}
// --8<-- [end:nearest]
