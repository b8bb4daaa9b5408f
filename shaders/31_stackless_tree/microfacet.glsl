// Metals: the Fresnel equations of a conductor, and a rough surface as a sea of tiny
// mirrors (GGX microfacets), each function a port of python_prototypes/microfacet.py,
// which tests/python/test_15_metals.py compares them with, sample by sample.
//
// Mitsuba 3's conventions: directions are unit vectors in the shading frame, the
// normal along +z, so a direction's cos(theta) is its z. wi points back to where the
// path came from (the camera's side), wo is where it goes next. An `eval` returns the
// BSDF times cos(theta_o), as Mitsuba's does; the path tracer divides it by the pdf.
// Needs PI (sampling.glsl).

// --8<-- [start:fresnel]
// Complex numbers as vec2(real, imaginary): just what the Fresnel equations need.
vec2 complexMul(vec2 a, vec2 b) { return vec2(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x); }
vec2 complexDiv(vec2 a, vec2 b) { return complexMul(a, vec2(b.x, -b.y)) / dot(b, b); }
// The principal square root (real part >= 0): in the metal, the wave decays.
vec2 complexSqrt(vec2 z) {
    float r = length(z);
    float imaginary = sqrt(max(0.0, 0.5 * (r - z.x)));
    return vec2(sqrt(max(0.0, 0.5 * (r + z.x))), z.y >= 0.0 ? imaginary : -imaginary);
}

// The reflected fraction of unpolarised light arriving at cos(theta) = cosI (> 0) on
// a metal of complex index n = eta + i k: the dielectric's formulas with n complex,
// where Snell's law gives n cos(theta_t) = sqrt(n^2 - sin^2(theta_i)).
float fresnelConductor(float cosI, float eta, float k) {
    vec2 n = vec2(eta, k), c = vec2(cosI, 0.0);
    vec2 nSquared = complexMul(n, n);
    vec2 nCosT = complexSqrt(nSquared - vec2(1.0 - cosI * cosI, 0.0));
    vec2 rs = complexDiv(c - nCosT, c + nCosT);
    vec2 rp = complexDiv(complexMul(nSquared, c) - nCosT, complexMul(nSquared, c) + nCosT);
    return 0.5 * (dot(rs, rs) + dot(rp, rp));
}

// Per channel: eta and k are measured at a red, a green and a blue wavelength.
vec3 fresnelConductor(float cosI, vec3 eta, vec3 k) {
    return vec3(fresnelConductor(cosI, eta.r, k.r), fresnelConductor(cosI, eta.g, k.g),
                fresnelConductor(cosI, eta.b, k.b));
}
// --8<-- [end:fresnel]

// --8<-- [start:ggx]
// GGX (Trowbridge-Reitz): the density of microfacet normals m per steradian, for the
// roughness alpha, normalised so that the microfacets' projected areas add up to the
// surface's own: the integral of D(m) cos(theta_m) over the hemisphere is 1.
float ggxD(vec3 m, float alpha) {
    if (m.z <= 0.0) return 0.0;  // every microfacet faces up
    float alpha2 = alpha * alpha;
    float stretched = (m.x * m.x + m.y * m.y) / alpha2 + m.z * m.z;
    return 1.0 / (PI * alpha2 * stretched * stretched);
}

// Smith's G1: the fraction of the microfacets with normal m that direction v sees,
// 1 / (1 + Lambda(v)), Lambda the area hidden from v relative to the area it sees.
// A microfacet turned away from v (v.m of another sign than v.z) is not seen at all.
float ggxG1(vec3 v, vec3 m, float alpha) {
    if (dot(v, m) * v.z <= 0.0) return 0.0;
    float tanSquared = (v.x * v.x + v.y * v.y) / (v.z * v.z);
    float lambda = 0.5 * (sqrt(1.0 + alpha * alpha * tanSquared) - 1.0);
    return 1.0 / (1.0 + lambda);
}

// Masking (from wi) and shadowing (from wo) as independent events: Mitsuba 3's choice.
float ggxG(vec3 wi, vec3 wo, vec3 m, float alpha) {
    return ggxG1(wi, m, alpha) * ggxG1(wo, m, alpha);
}
// --8<-- [end:ggx]

// --8<-- [start:visible_normals]
// Shirley and Chiu's map of the unit square onto the unit disk, which keeps areas:
// Mitsuba's, so the same (u1, u2) gives Mitsuba's microfacet normal.
vec2 squareToDisk(vec2 u) {
    vec2 p = 2.0 * u - 1.0;
    if (p.x == 0.0 && p.y == 0.0) return vec2(0.0);
    bool radiusIsX = abs(p.x) >= abs(p.y);
    float r = radiusIsX ? p.x : p.y;
    float phi = radiusIsX ? (PI / 4.0) * (p.y / p.x) : PI / 2.0 - (PI / 4.0) * (p.x / p.y);
    return r * vec2(cos(phi), sin(phi));
}

// A microfacet normal drawn with the density of the normals wi sees (Heitz 2018):
// visibleNormalPdf below. GGX is the normal distribution of an ellipsoid of radii
// (1/alpha, 1/alpha, 1); stretched into a hemisphere, its visible normals are its
// points, spread evenly over the disk they cover as seen from (stretched) wi.
vec3 sampleVisibleNormal(vec3 wi, float alpha, vec2 u) {
    vec3 wiStretched = normalize(vec3(alpha * wi.xy, wi.z));
    // A frame around it: t1 across the plane of incidence (Mitsuba's -y from above).
    float across = length(wiStretched.xy);
    vec3 t1 = across > 0.0 ? vec3(wiStretched.y, -wiStretched.x, 0.0) / across
                           : vec3(0.0, -1.0, 0.0);
    vec3 t2 = cross(t1, wiStretched);
    // Seen from wi, the hemisphere covers half a disk and half an ellipse: squeeze each
    // chord of the disk onto that shape, which keeps the points evenly spread.
    vec2 p = squareToDisk(u);
    float s = 0.5 * (1.0 + wiStretched.z);
    p.y = (1.0 - s) * sqrt(1.0 - p.x * p.x) + s * p.y;
    // Lift the point along wi onto the hemisphere; its normal there, unstretched
    // (normals scale by the inverse transpose of the stretch: x and y by alpha).
    float height = sqrt(max(0.0, 1.0 - dot(p, p)));
    vec3 normal = p.x * t1 + p.y * t2 + height * wiStretched;
    return normalize(vec3(alpha * normal.xy, max(0.0, normal.z)));
}

// The density of sampleVisibleNormal's m, per steradian of m: the microfacets with
// normal m that wi sees, weighted by the area they show it, G1 (wi.m) D / cos(theta_i).
float visibleNormalPdf(vec3 wi, vec3 m, float alpha) {
    return ggxG1(wi, m, alpha) * max(0.0, dot(wi, m)) * ggxD(m, alpha) / wi.z;
}
// --8<-- [end:visible_normals]

// --8<-- [start:rough_conductor]
// wi mirrored about the (micro)normal m.
vec3 reflectAbout(vec3 wi, vec3 m) { return 2.0 * dot(wi, m) * m - wi; }

// f(wi, wo) cos(theta_o) = F D G / (4 cos(theta_i)): only the microfacets with the half
// vector for their normal reflect wi into wo.
vec3 roughConductorEval(vec3 wi, vec3 wo, float alpha, vec3 eta, vec3 k) {
    if (wi.z <= 0.0 || wo.z <= 0.0) return vec3(0.0);
    vec3 m = normalize(wi + wo);
    float value = ggxD(m, alpha) * ggxG(wi, wo, m, alpha) / (4.0 * wi.z);
    return fresnelConductor(dot(wi, m), eta, k) * value;
}

// The density of roughConductorSample's wo: the visible normal's density, times the
// Jacobian of reflection: a patch of wo's around wo covers 1 / (4 wo.m) as many m's.
float roughConductorPdf(vec3 wi, vec3 wo, float alpha) {
    if (wi.z <= 0.0 || wo.z <= 0.0) return 0.0;
    vec3 m = normalize(wi + wo);
    if (dot(wo, m) <= 0.0) return 0.0;
    return visibleNormalPdf(wi, m, alpha) / (4.0 * dot(wo, m));
}

// A sampled direction, its weight eval / pdf (0 for a failed sample) and its pdf.
struct BsdfSample {
    vec3 wo;
    vec3 weight;
    float pdf;
};

// Reflect wi about a visible normal. eval / pdf simplifies to F G1(wo): D, G1(wi) and
// the cosines cancel, which is why sampling the visible normals is worth its trouble.
BsdfSample roughConductorSample(vec3 wi, float alpha, vec3 eta, vec3 k, vec2 u) {
    vec3 m = sampleVisibleNormal(wi, alpha, u);
    vec3 wo = reflectAbout(wi, m);
    float pdf = roughConductorPdf(wi, wo, alpha);
    if (pdf <= 0.0) return BsdfSample(wo, vec3(0.0), 0.0);  // under the surface
    return BsdfSample(wo, roughConductorEval(wi, wo, alpha, eta, k) / pdf, pdf);
}
// --8<-- [end:rough_conductor]
