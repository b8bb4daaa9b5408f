// Choosing directions at random, each with the probability density the estimator
// divides by.

const float PI = 3.14159265358979;

// Two random numbers, in this order (GLSL leaves the order of a call's arguments open).
vec2 random2(inout RandomState random) {
    float u = random01(random);
    return vec2(u, random01(random));
}

// A right-handed orthonormal basis around a unit normal, without branches or
// normalisation (Duff et al. 2017, "Building an orthonormal basis, revisited").
mat3 basisAround(vec3 n) {
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float b = n.x * n.y * a;
    return mat3(vec3(1.0 + s * n.x * n.x * a, s * b, -s * n.x),
                vec3(b, s + n.y * n.y * a, -n.y), n);
}

// --8<-- [start:cosine]
// A direction above the surface with density cos(theta) / pi per steradian (Malley's
// method): a uniform point on the unit disk, lifted onto the hemisphere. Directions
// near the normal, which a Lambertian surface weights most, come up most often.
vec3 cosineSampleHemisphere(vec3 normal, vec2 u) {
    // BEGIN SOLUTION a uniform point on the unit disk (radius sqrt(u.x)), lifted up
    float radius = sqrt(u.x);
    float angle = 2.0 * PI * u.y;
    vec3 local = vec3(radius * cos(angle), radius * sin(angle), sqrt(max(0.0, 1.0 - u.x)));
    return basisAround(normal) * local;
    // STUB: return normal;
    // END SOLUTION
}
// --8<-- [end:cosine]
