// Choosing directions and points at random, each with the probability density the
// estimator divides by.

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
    float radius = sqrt(u.x);
    float angle = 2.0 * PI * u.y;
    vec3 local = vec3(radius * cos(angle), radius * sin(angle), sqrt(max(0.0, 1.0 - u.x)));
    return basisAround(normal) * local;
}
// --8<-- [end:cosine]


// A point on an emitter, picked uniformly by area.
struct LightPoint {
    vec3 position;
    vec3 normal;    // unit, the emitting side
    vec3 emission;  // its radiance
};

// --8<-- [start:sample_emitter]
LightPoint sampleEmitter(Emitter emitter, vec2 u) {
    LightPoint light;
    uint material;
    if (emitter.shape == SHAPE_QUAD) {
        Quad q = quadAt(int(emitter.index));
        light.position = q.origin + u.x * q.edge1 + u.y * q.edge2;
        light.normal = normalize(cross(q.edge1, q.edge2));
        material = q.material;
    } else if (emitter.shape == SHAPE_TRIANGLE) {
        Triangle triangle = triangleAt(emitter.index);
        Corners t = cornersOf(triangle);
        // sqrt spreads the points evenly: without it they bunch up at p0.
        float s = sqrt(u.x);
        light.position = (1.0 - s) * t.p0 + s * (1.0 - u.y) * t.p1 + s * u.y * t.p2;
        light.normal = normalize(cross(t.p1 - t.p0, t.p2 - t.p0));
        material = triangle.material;
    } else {
        // Uniform on the whole sphere; points on the far side face away and add nothing.
        Sphere s = sphereAt(int(emitter.index));
        float z = 1.0 - 2.0 * u.x, r = sqrt(max(0.0, 1.0 - z * z));
        float angle = 2.0 * PI * u.y;
        light.normal = vec3(r * cos(angle), r * sin(angle), z);
        light.position = s.center + s.radius * light.normal;
        material = s.material;
    }
    light.emission = materialAt(material).emission.rgb;
    return light;
}
// --8<-- [end:sample_emitter]

// --8<-- [start:light_pdf]
// The density, per steradian seen from the shading point, of light sampling choosing
// a point at `distance` whose normal makes cos(theta) = cosLight with the ray: the
// shapes rather than the environment (1 - environmentChance), one emitter of
// EMITTER_COUNT, then 1 / area per square metre, and a small patch dA at that
// distance and angle covers dA cosLight / distance^2 steradians.
float lightPdf(uint emitter, float distance, float cosLight) {
    float areaPdf = (1.0 - environmentChance) /
                    (float(EMITTER_COUNT) * emitterAt(emitter).area);
    return areaPdf * distance * distance / cosLight;
}
// --8<-- [end:light_pdf]

// --8<-- [start:power_heuristic]
// Veach's power heuristic (beta = 2) for the sample drawn with density `pdf` when the
// other strategy has density `otherPdf`: pdf^2 / (pdf^2 + otherPdf^2), written so that
// a huge density (a light seen edge-on) gives 1 instead of inf / inf.
float powerHeuristic(float pdf, float otherPdf) {
    float ratio = otherPdf / pdf;
    return 1.0 / (1.0 + ratio * ratio);
}
// --8<-- [end:power_heuristic]
