// Media whose density varies from place to place: a grid of densities (Mitsuba's .vol
// format, read by media.cpp) looked up with trilinear interpolation, and the two ways
// of travelling through it with no closed form for its transmittance: delta tracking
// for free flights, ratio tracking for shadow rays. Needs shared.h, random.glsl,
// media.glsl (Medium, FreeFlight) and FOREVER.

// --8<-- [start:density]
// Every grid's densities, one after another (Medium::firstValue), x fastest, then y,
// then z; four floats to a texel, their bits as they are (course::BufferTexture).
layout(binding = DENSITIES_UNIT) uniform usamplerBuffer densities;

float gridValue(Medium medium, ivec3 cell) {
    uvec3 size = medium.resolution;
    uint index = medium.firstValue + (uint(cell.z) * size.y + uint(cell.y)) * size.x +
                 uint(cell.x);
    return uintBitsToFloat(texelFetch(densities, int(index >> 2u))[index & 3u]);
}

// The density at `position`: trilinear between the values at the centres of the eight
// cells around it (a value sits at its cell's centre, Mitsuba's convention). Within
// half a cell of the box's faces the nearest face's values hold; outside the box, 0.
float densityAt(Medium medium, vec3 position) {
    vec3 inBox = (position - medium.boxMin) / (medium.boxMax - medium.boxMin);
    if (any(lessThan(inBox, vec3(0.0))) || any(greaterThan(inBox, vec3(1.0)))) return 0.0;
    // BEGIN SOLUTION the cell below, the fraction of the way to the next; clamped corners
    vec3 cells = inBox * vec3(medium.resolution) - 0.5;
    vec3 below = floor(cells);
    vec3 f = cells - below;
    ivec3 last = ivec3(medium.resolution) - 1;
    ivec3 c0 = clamp(ivec3(below), ivec3(0), last);
    ivec3 c1 = clamp(ivec3(below) + 1, ivec3(0), last);
    float x00 = mix(gridValue(medium, c0), gridValue(medium, ivec3(c1.x, c0.y, c0.z)), f.x);
    float x10 = mix(gridValue(medium, ivec3(c0.x, c1.y, c0.z)),
                    gridValue(medium, ivec3(c1.x, c1.y, c0.z)), f.x);
    float x01 = mix(gridValue(medium, ivec3(c0.x, c0.y, c1.z)),
                    gridValue(medium, ivec3(c1.x, c0.y, c1.z)), f.x);
    float x11 = mix(gridValue(medium, ivec3(c0.x, c1.y, c1.z)), gridValue(medium, c1), f.x);
    return mix(mix(x00, x10, f.y), mix(x01, x11, f.y), f.z);
    // STUB: return gridValue(medium, ivec3(inBox * vec3(medium.resolution - 1u)));  // nearest
    // END SOLUTION
}
// --8<-- [end:density]

// Where `ray` is inside the grid's box, within [0, distance]: false if nowhere.
bool throughBox(Medium medium, Ray ray, float distance, out float near, out float far) {
    vec3 inverse = 1.0 / ray.direction;
    vec3 t0 = (medium.boxMin - ray.origin) * inverse;
    vec3 t1 = (medium.boxMax - ray.origin) * inverse;
    vec3 low = min(t0, t1), high = max(t0, t1);
    near = max(max(low.x, low.y), max(low.z, 0.0));
    far = min(min(high.x, high.y), min(high.z, distance));
    return near < far;
}

// --8<-- [start:delta]
// Delta tracking: steps of a homogeneous medium as dense as the grid's densest point
// (the majorant), each step's end a real collision with the chance sigma_t / majorant
// there, else a "null" one that changes nothing and the walk goes on. The first real
// collision is distributed exactly as the grid's free flights: at a real one the ray
// scatters, with the albedo as its weight; past the surface, the ray reaches it.
FreeFlight deltaTracking(Medium medium, Ray ray, float surfaceDistance,
                         inout RandomState random) {
    FreeFlight flight;
    flight.scattered = false;
    flight.distance = surfaceDistance;
    flight.weight = vec3(1.0);
    float t, far;
    if (!throughBox(medium, ray, surfaceDistance, t, far)) return flight;
    for (int step = 0; step < MAX_TRACKING_STEPS; ++step) {
        // BEGIN SOLUTION a majorant step; a real collision with chance sigma_t / majorant
        t -= log(1.0 - random01(random)) / medium.majorant;
        if (t >= far) return flight;
        float sigmaT = medium.scale * densityAt(medium, ray.origin + t * ray.direction);
        if (random01(random) * medium.majorant < sigmaT) {
            flight.scattered = true;
            flight.distance = t;
            flight.weight = medium.albedo;
            return flight;
        }
        // STUB: return flight;  // the grid is seen through, as if empty
        // END SOLUTION
    }
    flight.weight = vec3(0.0);  // out of steps (chance below 1e-20): the path ends
    return flight;
}
// --8<-- [end:delta]

// --8<-- [start:ratio]
// Ratio tracking: the same steps, but instead of ending at a real collision the walk
// multiplies in the chance of a null one, 1 - sigma_t / majorant, at each. Its mean is
// the transmittance, and it is never the all-or-nothing estimate delta tracking would
// give a shadow ray.
float ratioTracking(Medium medium, Ray ray, float distance, inout RandomState random) {
    float t, far;
    if (!throughBox(medium, ray, distance, t, far)) return 1.0;
    float kept = 1.0;
    for (int step = 0; step < MAX_TRACKING_STEPS; ++step) {
        // BEGIN SOLUTION a majorant step; keep the chance of a null collision
        t -= log(1.0 - random01(random)) / medium.majorant;
        if (t >= far) return kept;
        float sigmaT = medium.scale * densityAt(medium, ray.origin + t * ray.direction);
        kept *= 1.0 - sigmaT / medium.majorant;
        // STUB: return kept;  // nothing kept back
        // END SOLUTION
    }
    return 0.0;  // out of steps (chance below 1e-20): counted as blocked
}
// --8<-- [end:ratio]

// A medium of either kind: where the ray scatters, and what a shadow ray keeps.
FreeFlight flyThrough(Medium medium, Ray ray, float surfaceDistance,
                      inout RandomState random) {
    return medium.kind == MEDIUM_GRID
               ? deltaTracking(medium, ray, surfaceDistance, random)
               : sampleFreeFlight(medium, surfaceDistance, random2(random));
}

vec3 transmittanceAlong(Medium medium, Ray ray, float distance, inout RandomState random) {
    return medium.kind == MEDIUM_GRID ? vec3(ratioTracking(medium, ray, distance, random))
                                      : transmittanceThrough(medium, distance);
}
