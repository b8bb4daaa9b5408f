// Glass: the Fresnel equations of a dielectric, Snell's law, and a rough interface as
// GGX microfacets that reflect or refract. Each function is a port of
// python_prototypes/microfacet.py, which tests/python/test_16_glass.py compares them
// with, query by query.
//
// microfacet.glsl's conventions, and one more: the shading frame's z is the surface's
// outward normal, so wi.z < 0 means the path arrived from inside the glass. `eta` is
// the index inside over the index outside (air: 1), seen from outside; a ray from
// inside sees 1 / eta. Needs microfacet.glsl.

// --8<-- [start:fresnel]
// What light does at a smooth boundary between two dielectrics.
struct Fresnel {
    float reflectance;  // F, the reflected fraction; 1 under total internal reflection
    float cosT;         // cos(theta_t): of the opposite sign to cos(theta_i), 0 under TIR
    float etaIT;        // eta_t / eta_i along the way: eta from outside, 1 / eta inside
    float etaTI;        // its inverse, which scales the refracted direction's tangent part
};

// The unpolarised reflectance at cos(theta_i) = cosI (negative from inside).
Fresnel fresnelDielectric(float cosI, float eta) {
    bool fromOutside = cosI >= 0.0;
    float etaIT = fromOutside ? eta : 1.0 / eta;
    float etaTI = 1.0 / etaIT;
    // Snell: sin(theta_t) = (eta_i / eta_t) sin(theta_i). Beyond 1, no ray gets through.
    float sinTSquared = etaTI * etaTI * (1.0 - cosI * cosI);
    if (sinTSquared >= 1.0) return Fresnel(1.0, 0.0, etaIT, etaTI);  // total reflection
    float cosIAbs = abs(cosI), cosTAbs = sqrt(1.0 - sinTSquared);
    float rs = (cosIAbs - etaIT * cosTAbs) / (cosIAbs + etaIT * cosTAbs);
    float rp = (etaIT * cosIAbs - cosTAbs) / (etaIT * cosIAbs + cosTAbs);
    float reflectance = cosIAbs == 0.0 ? 1.0 : 0.5 * (rs * rs + rp * rp);
    if (eta == 1.0) reflectance = 0.0;  // no boundary at all
    return Fresnel(reflectance, fromOutside ? -cosTAbs : cosTAbs, etaIT, etaTI);
}

// Snell's law about the (micro)normal m: the part of wi along the surface shrinks by
// etaTI and turns round; the part along m becomes cosT, on the far side.
vec3 refractAbout(vec3 wi, vec3 m, float cosT, float etaTI) {
    vec3 alongSurface = wi - dot(wi, m) * m;
    return cosT * m - etaTI * alongSurface;
}
// --8<-- [end:fresnel]

// --8<-- [start:smooth]
// A smooth boundary reflects with probability F, else refracts: each choice's weight,
// F / F or (1 - F) / (1 - F), is 1, except that refracted radiance is scaled by
// etaTI^2 (the page says why). Both directions are deltas: pdf 0.
BsdfSample smoothDielectricSample(vec3 wi, float eta, float u) {
    Fresnel fresnel = fresnelDielectric(wi.z, eta);
    if (u <= fresnel.reflectance) return BsdfSample(vec3(-wi.xy, wi.z), vec3(1.0), 0.0);
    vec3 wo = refractAbout(wi, vec3(0.0, 0.0, 1.0), fresnel.cosT, fresnel.etaTI);
    float radianceScale = fresnel.etaTI * fresnel.etaTI;
    return BsdfSample(wo, vec3(radianceScale), 0.0);
}
// --8<-- [end:smooth]

// --8<-- [start:rough]
// eta on the far side of the boundary over eta on wi's side.
float etaBeyond(vec3 wi, float eta) { return wi.z > 0.0 ? eta : 1.0 / eta; }

// The microfacet normal that scatters wi into wo, facing up: along wi + wo for a
// reflection, wi + eta wo for a refraction (Walter et al. 2007).
vec3 generalizedHalfVector(vec3 wi, vec3 wo, float eta) {
    float scale = wi.z * wo.z > 0.0 ? 1.0 : etaBeyond(wi, eta);
    vec3 m = normalize(wi + scale * wo);
    return m.z < 0.0 ? -m : m;
}

// How much a patch of refracted directions around wo shrinks as normals around m:
// d omega_m / d omega_o (Walter et al. 2007, eq. 17).
float transmissionJacobian(vec3 wi, vec3 wo, vec3 m, float etaIT) {
    float denominator = dot(wi, m) + etaIT * dot(wo, m);
    return etaIT * etaIT * abs(dot(wo, m)) / (denominator * denominator);
}
float reflectionJacobian(vec3 wo, vec3 m) { return 1.0 / (4.0 * abs(dot(wo, m))); }

// f(wi, wo) |cos(theta_o)|, wi and wo on either side. Each lobe is the light of the
// microfacets wi sees with normal m, F D G |wi.m| / |cos(theta_i)| (1 - F for
// refraction), times the lobe's Jacobian; refraction also scales radiance by 1/eta^2.
float roughDielectricEval(vec3 wi, vec3 wo, float alpha, float eta) {
    if (wi.z == 0.0) return 0.0;
    vec3 m = generalizedHalfVector(wi, wo, eta);
    float reflectance = fresnelDielectric(dot(wi, m), eta).reflectance;
    float seen = ggxD(m, alpha) * ggxG(wi, wo, m, alpha) * abs(dot(wi, m) / wi.z);
    if (wi.z * wo.z > 0.0) return reflectance * seen * reflectionJacobian(wo, m);
    float etaIO = etaBeyond(wi, eta), radianceScale = 1.0 / (etaIO * etaIO);
    return radianceScale * (1.0 - reflectance) * seen * transmissionJacobian(wi, wo, m, etaIO);
}

// The density of roughDielectricSample's wo over the whole sphere: the visible
// normal's, times the chance of the lobe, times its Jacobian.
float roughDielectricPdf(vec3 wi, vec3 wo, float alpha, float eta) {
    if (wi.z == 0.0) return 0.0;
    bool reflection = wi.z * wo.z > 0.0;
    vec3 m = generalizedHalfVector(wi, wo, eta);
    if (dot(wi, m) * wi.z <= 0.0 || dot(wo, m) * wo.z <= 0.0) return 0.0;  // hidden
    float reflectance = fresnelDielectric(dot(wi, m), eta).reflectance;
    float jacobian = reflection ? reflectionJacobian(wo, m)
                                : transmissionJacobian(wi, wo, m, etaBeyond(wi, eta));
    vec3 wiAbove = wi.z < 0.0 ? -wi : wi;  // inside, wi sees the microfacets' backs
    return visibleNormalPdf(wiAbove, m, alpha) *
           (reflection ? reflectance : 1.0 - reflectance) * jacobian;
}

// A visible normal, then reflection with probability F or refraction: the weight
// eval / pdf simplifies to G / G1(wi), times the radiance scale for a refraction.
// u.xy picks the normal, u.z the lobe.
BsdfSample roughDielectricSample(vec3 wi, float alpha, float eta, vec3 u) {
    vec3 wiAbove = wi.z < 0.0 ? -wi : wi;
    vec3 m = sampleVisibleNormal(wiAbove, alpha, u.xy);
    Fresnel fresnel = fresnelDielectric(dot(wi, m), eta);
    bool reflection = u.z <= fresnel.reflectance;
    vec3 wo = reflection ? reflectAbout(wi, m)
                         : refractAbout(wi, m, fresnel.cosT, fresnel.etaTI);
    float jacobian = reflection ? reflectionJacobian(wo, m)
                                : transmissionJacobian(wi, wo, m, fresnel.etaIT);
    float pdf = visibleNormalPdf(wiAbove, m, alpha) *
                (reflection ? fresnel.reflectance : 1.0 - fresnel.reflectance) * jacobian;
    float weight = ggxG(wi, wo, m, alpha) / ggxG1(wi, m, alpha) *
                   (reflection ? 1.0 : fresnel.etaTI * fresnel.etaTI);
    // A reflection must stay on wi's side of the surface, a refraction cross it.
    bool sideOk = reflection ? wi.z * wo.z > 0.0 : wi.z * wo.z < 0.0;
    if (!sideOk || wi.z == 0.0 || !(pdf > 0.0)) return BsdfSample(wo, vec3(0.0), 0.0);
    return BsdfSample(wo, vec3(weight), pdf);
}
// --8<-- [end:rough]
