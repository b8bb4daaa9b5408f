// What a ray found. Every kind of surface fills one in; later chapters add to it.

// --8<-- [start:hit]
struct Hit {
    float t;        // how far along the ray
    vec3 position;
    vec3 normal;           // unit length, facing the ray: the normal to shade with
    vec3 geometricNormal;  // the flat triangle's, facing the ray: shadow rays start along it
    vec3 albedo;    // the share of red, green and blue light the surface reflects
    vec2 barycentric;  // triangles: (u, v), the weights of corners p1 and p2
};
// --8<-- [end:hit]
