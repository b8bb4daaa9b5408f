// Chapter 21's path tracer cut into steps: one path's state (PathState), what a path
// gains when its ray leaves the scene (leaveScene), and everything done at a hit
// (shadeHit), which ends with the next ray and, for next-event estimation, a shadow ray
// still to trace (ShadowRay). The megakernel (path.comp) runs the steps in a loop per
// pixel; the wavefront (wavefront_*.comp, chapter 23) runs each as a kernel of its own
// over a queue of paths. The operations and the random numbers are chapter 21's, in
// its order, so it draws chapter 21's picture.
// Needs scene.glsl, sampling.glsl, environment.glsl and bsdf.glsl.

const float FOREVER = 3.0e38;

// A point just off the surface, on the side `normal` points to: float32 rounds a hit
// point to within a few units in the last place of its coordinates, so the gap grows
// with their size.
vec3 offsetFromSurface(vec3 position, vec3 normal) {
    vec3 size = abs(position);
    return position + RAY_OFFSET * (1.0 + max(size.x, max(size.y, size.z))) * normal;
}

// --8<-- [start:state]
// One path between bounces: the ray it is about to trace, the light gathered so far,
// and what the next hit needs to weigh its light.
struct PathState {
    Ray ray;
    vec3 radiance;
    vec3 throughput;     // the product of (BSDF cos / pdf) so far
    float directionPdf;  // the density with which BSDF sampling chose `ray`
    bool afterDelta;     // chosen by a delta BSDF: no NEE could find that light
    int bounce;          // surfaces hit so far
};

// Next-event estimation's shadow ray, still to be traced: if nothing lies between
// origin and origin + tMax direction, the path gains `light` (throughput included).
// tMax 0: there is none (the sample's light is zero, or the light is behind).
struct ShadowRay {
    Ray ray;
    float tMax;
    vec3 light;
};
// --8<-- [end:state]

PathState startPath(Ray ray) {
    return PathState(ray, vec3(0.0), vec3(1.0), 0.0, false, 0);
}

const ShadowRay NO_SHADOW_RAY = ShadowRay(Ray(vec3(0.0), vec3(0.0, 0.0, 1.0)), 0.0, vec3(0.0));

// Next-event estimation towards the environment: a direction picked by its tables, its
// radiance reflected towards the viewer, divided by the density of the choice (the
// chance of sampling the environment at all, times the tables' density), weighted by
// MIS against BSDF sampling; it counts if nothing is in the way.
ShadowRay lightFromEnvironment(Hit hit, Material material, mat3 frame, vec3 toViewer,
                               vec3 throughput, inout RandomState random) {
    float pdf;
    vec3 radiance;
    vec3 direction = sampleEnvironment(random2(random), pdf, radiance);
    if (pdf <= 0.0) return NO_SHADOW_RAY;
    if (dot(hit.normal, direction) * dot(hit.geometricNormal, direction) <= 0.0)
        return NO_SHADOW_RAY;
    vec3 reflected = bsdfEval(material, frame, toViewer, direction);  // f cos
    if (reflected == vec3(0.0)) return NO_SHADOW_RAY;
    vec3 side = dot(direction, hit.geometricNormal) > 0.0 ? hit.geometricNormal
                                                           : -hit.geometricNormal;
    pdf *= environmentChance;
    float weight = estimator == ESTIMATOR_MIS
                       ? powerHeuristic(pdf, bsdfPdf(material, frame, toViewer, direction))
                       : 1.0;
    return ShadowRay(Ray(offsetFromSurface(hit.position, side), direction), FOREVER,
                     throughput * (radiance * reflected / pdf * weight));
}

// Next-event estimation: the light arriving at the hit straight from one point picked
// on one emitter, reflected towards the viewer by the material's BSDF and divided by
// the density of the choice; with MIS, weighted against the BSDF sampling that could
// have found the same point. With an environment, it is the light sampled instead with
// probability environmentChance.
ShadowRay lightFromEmitters(Hit hit, Material material, mat3 frame, vec3 toViewer,
                            vec3 throughput, inout RandomState random) {
    // The draw is made with or without an environment, so that every way of compiling
    // the shader uses the same random numbers for the same pixel: the same picture.
    bool towardsEnvironment = random01(random) < environmentChance;
    if (HAS_ENVIRONMENT != 0 && towardsEnvironment)
        return lightFromEnvironment(hit, material, frame, toViewer, throughput, random);
    uint emitterCount = uint(EMITTER_COUNT);
    uint chosen = min(uint(random01(random) * float(emitterCount)), emitterCount - 1u);
    LightPoint light = sampleEmitter(emitterAt(chosen), random2(random));
    // The shadow ray leaves from the light's side of the surface: through glass, the
    // back. (The BSDF says whether anything gets there: nothing, for an opaque one.)
    vec3 lightSide = dot(light.position - hit.position, hit.geometricNormal) > 0.0
                         ? hit.geometricNormal : -hit.geometricNormal;
    vec3 origin = offsetFromSurface(hit.position, lightSide);
    vec3 toLight = light.position - origin;
    float distance = length(toLight);
    vec3 direction = toLight / distance;
    float cosLight = -dot(light.normal, direction);
    if (cosLight <= 0.0) return NO_SHADOW_RAY;  // behind the light
    // The flat and the smooth normal must put the light on the same side: BSDF
    // sampling ends other paths (chapter 11), so must this.
    if (dot(hit.normal, direction) * dot(hit.geometricNormal, direction) <= 0.0)
        return NO_SHADOW_RAY;
    vec3 reflected = bsdfEval(material, frame, toViewer, direction);  // f cos
    if (reflected == vec3(0.0)) return NO_SHADOW_RAY;  // no shadow ray for nothing
    // Stop short of the light by the same kind of gap, or the light itself is in the way.
    float stop = length(offsetFromSurface(light.position, light.normal) - light.position);
    float pdf = lightPdf(chosen, distance, cosLight);
    float weight = estimator == ESTIMATOR_MIS
                       ? powerHeuristic(pdf, bsdfPdf(material, frame, toViewer, direction))
                       : 1.0;
    return ShadowRay(Ray(origin, direction), distance - stop,
                     throughput * (light.emission * reflected / pdf * weight));
}

// Trace a shadow ray, if there is one: its light, or zero where something is in the way.
vec3 shadowRayLight(ShadowRay shadow, inout uint rays) {
    if (shadow.tMax == 0.0) return vec3(0.0);
    rays += 1u;
    return anyHit(shadow.ray, 0.0, shadow.tMax) ? vec3(0.0) : shadow.light;
}

// --8<-- [start:leave]
// The path's ray met nothing: the environment's light, counted as an emitter's is.
void leaveScene(inout PathState path) {
    if (!hasEnvironment()) return;
    float weight = 1.0;
    bool sampledOnly = path.bounce == 0 || path.afterDelta;
    if (!sampledOnly && estimator == ESTIMATOR_NEE) weight = 0.0;
    if (!sampledOnly && estimator == ESTIMATOR_MIS)
        weight = powerHeuristic(path.directionPdf,
                                environmentChance * environmentPdf(path.ray.direction));
    path.radiance += path.throughput * environmentRadiance(path.ray.direction) * weight;
}
// --8<-- [end:leave]

// --8<-- [start:shade]
// Everything done at a hit: the light it gives, the next-event estimate's shadow ray
// (`shadow`, still to trace), and the next direction. Returns false when the path ends
// here; else path.ray is the next ray to trace.
bool shadeHit(inout PathState path, Hit hit, inout RandomState random,
              out ShadowRay shadow) {
    shadow = NO_SHADOW_RAY;
    Ray ray = path.ray;
    Material material = materialAt(hit.material);
    material.albedo = albedoAt(material, hit.uv);  // a texture's, where it has one

    // 1. Light the ray runs into. The camera sees it in full, and so does a mirror;
    //    after another bounce, NEE has counted it already (weight 0) or shares it.
    if (hit.front && hit.emitter != NO_EMITTER) {
        float weight = 1.0;
        bool sampledOnly = path.bounce == 0 || path.afterDelta;
        if (!sampledOnly && estimator == ESTIMATOR_NEE) weight = 0.0;
        if (!sampledOnly && estimator == ESTIMATOR_MIS) {
            float cosLight = -dot(hit.geometricNormal, ray.direction);
            weight = powerHeuristic(path.directionPdf,
                                    lightPdf(hit.emitter, hit.t, cosLight));
        }
        path.radiance += path.throughput * material.emission * weight;
    }
    // A surface's back is black (as Mitsuba's), except glass's: a ray that meets it is
    // inside, on its way out. --depth ends the path.
    bool glass = isKind(material, MATERIAL_DIELECTRIC);
    if ((!hit.front && !glass) || path.bounce == maxBounces) return false;
    // The flat normal says which side the ray is on; where the smooth one disagrees the
    // path ends (chapter 11's rule for a front, now for both sides).
    if (dot(hit.normal, ray.direction) * dot(hit.geometricNormal, ray.direction) <= 0.0)
        return false;

    // 2. Light from the emitters straight to this point (next-event estimation), except
    //    at a delta BSDF, which reflects none of it. The shading frame: the smooth
    //    normal, outwards, so wi.z < 0 inside glass.
    mat3 frame = basisAround(hit.normal);
    vec3 toViewer = -ray.direction;
    path.afterDelta = isDelta(material);
    if (estimator != ESTIMATOR_BSDF && !path.afterDelta)
        shadow = lightFromEmitters(hit, material, frame, toViewer, path.throughput, random);

    // 3. The next direction, sampled by the material: the throughput picks up eval /
    //    pdf (the albedo for a Lambertian surface, F for a mirror).
    vec3 u = vec3(random2(random), random01(random));
    BsdfSample next = bsdfSample(material, frame, toViewer, u);
    if (next.weight == vec3(0.0)) return false;  // a failed sample
    // The side it leaves on, by the flat normal; the smooth one must agree.
    vec3 side = dot(next.wo, hit.geometricNormal) > 0.0 ? hit.geometricNormal
                                                        : -hit.geometricNormal;
    if (dot(next.wo, hit.normal) * dot(next.wo, hit.geometricNormal) <= 0.0) return false;
    path.directionPdf = next.pdf;
    path.throughput *= next.weight;

    // 4. Russian roulette: after a few bounces, a path carrying little light ends with
    //    probability 1 - survival; the survivors carry 1 / survival more, so the
    //    expected value is unchanged, only the noise grows a little.
    if (path.bounce + 1 >= ROULETTE_AFTER) {
        float survival = min(max(path.throughput.r, max(path.throughput.g,
                                                        path.throughput.b)), 0.95);
        if (random01(random) >= survival) return false;
        path.throughput /= survival;
    }
    path.ray = Ray(offsetFromSurface(hit.position, side), next.wo);
    path.bounce += 1;
    return true;
}
// --8<-- [end:shade]
