// A material's BSDF, whatever its kind: eval, pdf and sample, three functions that must
// agree (sample's weight is eval / pdf; tests/python/test_16_glass.py checks it).
// Directions are world vectors; `frame` turns shading-frame vectors (the smooth normal
// along z) into world ones, so each kind can work in microfacet.glsl's frame.
// Glass lets light through: its wi and wo may lie on either side (z < 0: inside).
// Needs Material (shared.h), PI and cosineSampleHemisphere (sampling.glsl),
// microfacet.glsl and dielectric.glsl.

// --8<-- [start:kind]
// Is the material of this kind? MATERIAL_KINDS (scene_code.glsl) has a bit for each
// kind the scene uses: a kind it does not use is never there, and when it uses only
// one, every material is of it. The compiler folds those answers, and drops the code
// of the kinds the scene has none of.
bool isKind(Material material, uint kind) {
    uint bit = 1u << kind;
    if ((MATERIAL_KINDS & bit) == 0u) return false;
    return MATERIAL_KINDS == bit || material.kind == kind;
}
// --8<-- [end:kind]

// --8<-- [start:delta]
// A mirror, a smooth metal and smooth glass scatter into one or two directions only:
// their BSDF is a Dirac delta. No light sample ever lands exactly there, so next-event
// estimation is useless at such a vertex; only sampling finds the light they scatter.
bool isDelta(Material material) {
    return isKind(material, MATERIAL_MIRROR) || (material.roughness == 0.0 &&
           (isKind(material, MATERIAL_CONDUCTOR) || isKind(material, MATERIAL_DIELECTRIC)));
}
// --8<-- [end:delta]

// --8<-- [start:eval_pdf]
// f(toViewer, toLight) cos(theta) at a vertex; zero for a delta BSDF (and below).
vec3 bsdfEval(Material material, mat3 frame, vec3 toViewer, vec3 toLight) {
    vec3 wi = toViewer * frame, wo = toLight * frame;  // world to shading frame
    if (isDelta(material)) return vec3(0.0);
    if (isKind(material, MATERIAL_DIELECTRIC))  // either side
        return vec3(roughDielectricEval(wi, wo, material.roughness, material.ior));
    if (wi.z <= 0.0 || wo.z <= 0.0) return vec3(0.0);
    if (isKind(material, MATERIAL_DIFFUSE)) return material.albedo * (wo.z / PI);
    if (!isKind(material, MATERIAL_CONDUCTOR)) return vec3(0.0);
    return roughConductorEval(wi, wo, material.roughness, material.eta, material.k);
}

// The density with which bsdfSample would choose toLight; zero for a delta BSDF (its
// density is infinite in one direction: such a sample is never MIS-weighted).
float bsdfPdf(Material material, mat3 frame, vec3 toViewer, vec3 toLight) {
    vec3 wi = toViewer * frame, wo = toLight * frame;
    if (isDelta(material)) return 0.0;
    if (isKind(material, MATERIAL_DIELECTRIC))
        return roughDielectricPdf(wi, wo, material.roughness, material.ior);
    if (wi.z <= 0.0 || wo.z <= 0.0) return 0.0;
    if (isKind(material, MATERIAL_DIFFUSE)) return wo.z / PI;
    if (!isKind(material, MATERIAL_CONDUCTOR)) return 0.0;
    return roughConductorPdf(wi, wo, material.roughness);
}
// --8<-- [end:eval_pdf]

// --8<-- [start:sample]
// The next direction (in the world) and its weight eval / pdf. A delta sample's pdf is
// returned as 0: a flag that its weight is F itself, with no density to divide by.
// u.xy picks a direction, u.z (glass only) between reflection and refraction.
BsdfSample bsdfSample(Material material, mat3 frame, vec3 toViewer, vec3 u) {
    vec3 wi = toViewer * frame;
    BsdfSample s = BsdfSample(vec3(0.0, 0.0, 1.0), vec3(0.0), 0.0);  // no kind: a failed one
    if (isKind(material, MATERIAL_DIFFUSE)) {  // cosine sampling: the weight is the albedo
        s.wo = cosineSampleHemisphere(vec3(0.0, 0.0, 1.0), u.xy);
        s = BsdfSample(s.wo, material.albedo, s.wo.z / PI);
    } else if (isKind(material, MATERIAL_MIRROR)) {
        s = BsdfSample(vec3(-wi.xy, wi.z), material.albedo, 0.0);
    } else if (isKind(material, MATERIAL_DIELECTRIC)) {
        s = material.roughness == 0.0 ? smoothDielectricSample(wi, material.ior, u.z)
                                      : roughDielectricSample(wi, material.roughness,
                                                              material.ior, u);
    } else if (isKind(material, MATERIAL_CONDUCTOR)) {
        // Smooth: a mirror with Fresnel; rough: GGX.
        s = material.roughness == 0.0
                ? BsdfSample(vec3(-wi.xy, wi.z),
                             fresnelConductor(wi.z, material.eta, material.k), 0.0)
                : roughConductorSample(wi, material.roughness, material.eta, material.k, u.xy);
    }
    s.wo = frame * s.wo;  // back to the world
    return s;
}
// --8<-- [end:sample]
