// What a ray found. Every kind of surface fills one in; later chapters add to it.

// --8<-- [start:hit]
struct Hit {
    float t;        // how far along the ray
    vec3 position;
    vec3 normal;    // unit length, pointing out of the surface
};
// --8<-- [end:hit]
