// Participating media (chapter 24): light travelling through fog, smoke or tinted
// glass is absorbed and scattered along the way, not only at surfaces. A medium has,
// per metre and per colour channel, an absorption coefficient sigma_a and a scattering
// coefficient sigma_s; their sum sigma_t is the extinction. The prototype,
// python_prototypes/media.py, checks each formula here against its closed form.

// --8<-- [start:beer]
// Beer-Lambert: the fraction of light that crosses `distance` metres of the medium
// without being absorbed or scattered away. (At FOREVER it is 0 wherever sigma_t > 0.)
vec3 sigmaT(Medium medium) { return medium.sigmaA + medium.sigmaS; }

vec3 transmittanceThrough(Medium medium, float distance) {
    return exp(-sigmaT(medium) * distance);
}
// --8<-- [end:beer]

// --8<-- [start:free_flight]
// How far a ray travels before the medium scatters it: free-flight sampling. For one
// channel c, t = -ln(1 - u) / sigma_t[c] has the density sigma_t[c] exp(-sigma_t[c] t),
// the transmittance's own shape. The channels' extinctions differ (a blue fog), so the
// channel is picked at random, each a third of the time, and the density of the
// distance is the mean of the three channels' densities: no channel's light is ever
// sampled with a density of zero, and the estimate stays unbiased (one-sample MIS over
// the channels, the balance heuristic).
struct FreeFlight {
    bool scattered;  // true: the medium scattered the ray at `distance`
    float distance;
    vec3 weight;     // what the throughput is multiplied by
};

FreeFlight sampleFreeFlight(Medium medium, float surfaceDistance, vec2 u) {
    FreeFlight flight;
    if (medium.sigmaS == vec3(0.0)) {  // it only absorbs: no scattering to sample, and
        flight.scattered = false;      // the transmittance is the weight (tinted glass)
        flight.distance = surfaceDistance;
        flight.weight = transmittanceThrough(medium, surfaceDistance);
        return flight;
    }
    vec3 extinction = sigmaT(medium);
    int channel = min(int(u.x * 3.0), 2);
    float t = extinction[channel] > 0.0 ? -log(1.0 - u.y) / extinction[channel] : FOREVER;
    flight.scattered = t < surfaceDistance;
    flight.distance = min(t, surfaceDistance);
    vec3 transmittance = transmittanceThrough(medium, flight.distance);
    // Scattered at t: density sigma_t T(t); reached the surface: probability T(surface).
    vec3 density = flight.scattered ? extinction * transmittance : transmittance;
    float pdf = (density.r + density.g + density.b) / 3.0;
    vec3 kept = flight.scattered ? medium.sigmaS * transmittance : transmittance;
    flight.weight = pdf > 0.0 ? kept / pdf : vec3(0.0);
    return flight;
}
// --8<-- [end:free_flight]

// --8<-- [start:phase]
// The Henyey-Greenstein phase function: the density, per steradian, of a scattered
// ray leaving at angle theta to the direction the light was travelling. Its mean
// cosine g sets the shape: 0 scatters evenly, g > 0 mostly onwards (fog, clouds),
// g < 0 mostly back. It integrates to 1 over the sphere.
float henyeyGreenstein(float cosTheta, float g) {
    float denominator = 1.0 + g * g - 2.0 * g * cosTheta;
    return (1.0 - g * g) / (4.0 * PI * denominator * sqrt(denominator));
}

// A direction with exactly that density (the inverse of its CDF in cos theta), so the
// phase function over its density is 1: the throughput is unchanged.
vec3 sampleHenyeyGreenstein(vec3 travelling, float g, vec2 u) {
    float cosTheta;
    if (abs(g) < 1e-3) {
        cosTheta = 1.0 - 2.0 * u.x;  // near 0: uniform over the sphere
    } else {
        float s = (1.0 - g * g) / (1.0 + g - 2.0 * g * u.x);
        cosTheta = (1.0 + g * g - s * s) / (2.0 * g);
    }
    float sinTheta = sqrt(max(0.0, 1.0 - cosTheta * cosTheta));
    float angle = 2.0 * PI * u.y;
    return basisAround(travelling) *
           vec3(sinTheta * cos(angle), sinTheta * sin(angle), cosTheta);
}
// --8<-- [end:phase]
