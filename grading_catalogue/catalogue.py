"""The catalogues of submissions for the statistical and traversal grading
(tools/course_tools/grading/grading_statistics.py), chapter by chapter: correct
implementations that differ from the solution (other random numbers, another valid
mapping or weighting), which must each score at least 90%, and plausible wrong ones,
which must each score at most half and which the grader's diagnosis names
(tools/course_tools/grading/diagnosis.py). Each is a few find-and-replace edits on a copy
of the solution's chapters/NN and shaders/NN (grading_catalogue/variant.py);
tests/python/tools/test_grading_statistics.py grades them."""

from __future__ import annotations

from grading_catalogue.variant import Edit, Variant

CATALOGUE: dict[str, list[Variant]] = {}


# ---------------------------------------------------------------- chapter 11

P = "11_path_tracing"
COSINE = """    float radius = sqrt(u.x);
    float angle = 2.0 * PI * u.y;
    vec3 local = vec3(radius * cos(angle), radius * sin(angle), sqrt(max(0.0, 1.0 - u.x)));
"""
UNIFORM = """    float z = u.x;  // cos(theta) uniform in [0, 1]: uniform over the hemisphere
    float radius = sqrt(max(0.0, 1.0 - z * z));
    float angle = 2.0 * PI * u.y;
    vec3 local = vec3(radius * cos(angle), radius * sin(angle), z);
"""
THROUGHPUT = "        throughput *= material.albedo.rgb;\n"
BOUNCE_END = "if (!hit.front || bounce == maxBounces) break;"


def swapped(text: str) -> str:
    return text.replace("u.x", "U.Y").replace("u.y", "u.x").replace("U.Y", "u.y")


CONCENTRIC = """    vec2 square = 2.0 * u - 1.0;
    vec2 disk = vec2(0.0);
    if (square.x != 0.0 || square.y != 0.0) {
        bool wide = abs(square.x) > abs(square.y);
        float radius = wide ? square.x : square.y;
        float angle = wide ? PI / 4.0 * (square.y / square.x)
                           : PI / 2.0 - PI / 4.0 * (square.x / square.y);
        disk = radius * vec2(cos(angle), sin(angle));
    }
    vec3 local = vec3(disk, sqrt(max(0.0, 1.0 - dot(disk, disk))));
"""

CHAPTER_11 = [
    Variant(P, "cosine sampler with u.x and u.y swapped", True, (
        Edit("shaders/sampling.glsl", COSINE, swapped(COSINE)),)),
    Variant(P, "concentric (Shirley-Chiu) disk mapping", True, (
        Edit("shaders/sampling.glsl", COSINE, CONCENTRIC),)),
    Variant(P, "uniform hemisphere sampling with its own density 1/(2 pi)", True, (
        Edit("shaders/sampling.glsl", COSINE, UNIFORM),
        Edit("shaders/path.comp", THROUGHPUT,
             "        throughput *= material.albedo.rgb * 2.0 * "
             "max(dot(hit.normal, direction), 0.0);\n"))),

    Variant(P, "uniform hemisphere directions treated as cosine-distributed", False, (
        Edit("shaders/sampling.glsl", COSINE, UNIFORM),),
        explanation=("Directions are drawn uniformly but weighted as if cosine-distributed, so "
                     "light at a slant is overcounted."),
        section="Cosine sampling"),
    Variant(P, "the BSDF's 1/pi kept in the throughput", False, (
        Edit("shaders/path.comp", THROUGHPUT,
             "        throughput *= material.albedo.rgb / PI;\n"),),
        explanation=("With cosine sampling the pi of f = albedo/pi cancels the pdf's; keeping "
                     "it darkens every bounce by pi."),
        section="Cosine sampling"),
    Variant(P, "the cosine multiplied in as well as sampled", False, (
        Edit("shaders/path.comp", THROUGHPUT,
             "        throughput *= material.albedo.rgb * "
             "max(dot(hit.normal, direction), 0.0);\n"),),
        explanation=("Cosine sampling already accounts for cos(theta); multiplying it in again "
                     "darkens all bounced light."),
        section="Cosine sampling"),
    Variant(P, "one bounce too many", False, (
        Edit("shaders/path.comp", BOUNCE_END,
             "if (!hit.front || bounce == maxBounces + 1) break;"),),
        explanation=("The path makes one bounce more than --depth allows, so it gathers too "
                     "much indirect light."),
        section="The path loop"),
    Variant(P, "one bounce too few", False, (
        Edit("shaders/path.comp", BOUNCE_END,
             "if (!hit.front || bounce + 1 == maxBounces) break;"),),
        explanation=("Stopping one bounce short of --depth loses the light of the last bounce: "
                     "the picture is too dark."),
        section="The path loop"),
    # Held out (the diagnosis must name "one bounce too many"): the loop counted from -1,
    # so the break at maxBounces comes after maxBounces + 1 bounces, as that one's does.
    Variant(P, "one bounce too many (the loop counted from -1)", False, (
        Edit("shaders/path.comp", "for (int bounce = 0;; ++bounce)",
             "for (int bounce = -1;; ++bounce)"),),
        explanation=("The path makes one bounce more than --depth allows, so it gathers too "
                     "much indirect light."),
        section="The path loop",
        held_out="one bounce too many"),
]


# ---------------------------------------------------------------- chapter 12

T = "12_light_sampling"
LIGHT_PDF = "    return areaPdf * distance * distance / cosLight;\n"
CHOICE = ("    uint chosen = min(uint(random01(random) * float(emitterCount)), "
          "emitterCount - 1u);\n")
HIT_WEIGHT = "weight = powerHeuristic(directionPdf, lightPdf(hit.emitter, hit.t, cosLight));"

CHAPTER_12 = [
    Variant(T, "random numbers drawn in another order (light point, then light)", True, (
        Edit("shaders/path.comp", CHOICE + "    LightPoint light = sampleEmitter(emitters"
             "[chosen], random2(random));\n",
             "    vec2 onLight = random2(random);\n" + CHOICE +
             "    LightPoint light = sampleEmitter(emitters[chosen], onLight);\n"),)),
    Variant(T, "balance heuristic instead of the power heuristic", True, (
        Edit("shaders/sampling.glsl", "return 1.0 / (1.0 + ratio * ratio);",
             "return 1.0 / (1.0 + ratio);"),)),
    Variant(T, "Russian roulette from the first bounce, survival at most 0.8", True, (
        Edit("shaders/path.comp", "if (bounce + 1 >= ROULETTE_AFTER) {",
             "if (bounce + 1 >= 1) {"),
        Edit("shaders/path.comp", "throughput.b)), 0.95);", "throughput.b)), 0.8);"))),
    Variant(T, "uniform hemisphere sampling with its own density 1/(2 pi)", True, (
        Edit("shaders/sampling.glsl", COSINE, UNIFORM),
        Edit("shaders/path.comp", "directionPdf = max(dot(hit.normal, direction), 0.0) / PI;"
             "\n        throughput *= albedo;",
             "directionPdf = 1.0 / (2.0 * PI);\n"
             "        throughput *= albedo * 2.0 * max(dot(hit.normal, direction), 0.0);"),
        Edit("shaders/path.comp", "powerHeuristic(pdf, cosSurface / PI)",
             "powerHeuristic(pdf, 1.0 / (2.0 * PI))"))),
    Variant(T, "lights chosen in proportion to their area", True, (
        Edit("shaders/path.comp", CHOICE, """    float totalArea = 0.0;
    for (uint i = 0u; i < emitterCount; ++i) totalArea += emitters[i].area;
    float pick = random01(random) * totalArea;
    uint chosen = 0u;
    while (chosen + 1u < emitterCount && pick >= emitters[chosen].area)
        pick -= emitters[chosen++].area;
"""),
        Edit("shaders/sampling.glsl",
             "    float areaPdf = 1.0 / (float(emitters.length()) * emitters[emitter].area);\n",
             """    float totalArea = 0.0;
    for (int i = 0; i < emitters.length(); ++i) totalArea += emitters[i].area;
    float areaPdf = 1.0 / totalArea;  // area_i / total, times 1 / area_i
"""))),

    Variant(T, "light density off by a factor of pi", False, (
        Edit("shaders/sampling.glsl", LIGHT_PDF,
             "    return areaPdf * distance * distance / cosLight / PI;\n"),),
        explanation=("The light's density is divided by an extra pi, so shadow rays bring back "
                     "too much light."),
        section="Next-event estimation"),
    Variant(T, "no cosine at the light", False, (
        Edit("shaders/sampling.glsl", LIGHT_PDF,
             "    return areaPdf * distance * distance;\n"),),
        explanation=("A light's density per steradian needs its cosine (dA cos / d^2); without "
                     "it, slanted light is too bright."),
        section="Next-event estimation"),
    Variant(T, "light density not divided by the number of lights", False, (
        Edit("shaders/sampling.glsl",
             "1.0 / (float(emitters.length()) * emitters[emitter].area)",
             "1.0 / emitters[emitter].area"),),
        explanation=("Picking one of N lights has chance 1/N; leaving it out of the light's "
                     "density makes direct light too bright."),
        section="Next-event estimation"),
    Variant(T, "MIS: a light hit by a bounce counted in full (weights sum to more than 1)",
            False, (Edit("shaders/path.comp", HIT_WEIGHT, "weight = 1.0;"),),
        explanation=("A light that a bounce runs into needs its MIS weight too; counted in "
                     "full, it is added twice (too bright)."),
        section="Multiple importance sampling"),
    Variant(T, "MIS: next-event weight with the densities swapped (weights do not sum to 1)",
            False, (Edit("shaders/path.comp", "powerHeuristic(pdf, cosSurface / PI)",
                         "powerHeuristic(cosSurface / PI, pdf)"),),
        explanation=("In the shadow ray's weight its own density comes first; swapped, the two "
                     "MIS weights no longer add up to 1."),
        section="Multiple importance sampling"),
    Variant(T, "Russian roulette without the division by the survival probability", False, (
        Edit("shaders/path.comp", "            throughput /= survival;\n", ""),),
        explanation=("Paths that survive Russian roulette must carry 1 / survival more; "
                     "without it indirect light is too dark."),
        section="Russian roulette"),
    Variant(T, "one bounce too many", False, (
        Edit("shaders/path.comp", BOUNCE_END,
             "if (!hit.front || bounce == maxBounces + 1) break;"),),
        explanation=("The path makes one bounce more than --depth allows, so it gathers too "
                     "much indirect light."),
        section="How it is checked"),
    Variant(T, "one bounce too few", False, (
        Edit("shaders/path.comp", BOUNCE_END,
             "if (!hit.front || bounce + 1 == maxBounces) break;"),),
        explanation=("Stopping one bounce short of --depth loses the light of the last bounce: "
                     "the picture is too dark."),
        section="How it is checked"),
    # Held out: the extra pi put into the area density instead of the returned value;
    # lightPdf, for NEE and for the MIS weights alike, is pi times too small either way.
    Variant(T, "light density off by a factor of pi (written another way)", False, (
        Edit("shaders/sampling.glsl",
             "1.0 / (float(emitters.length()) * emitters[emitter].area)",
             "1.0 / (PI * float(emitters.length()) * emitters[emitter].area)"),),
        explanation=("The light's density is divided by an extra pi, so shadow rays bring back "
                     "too much light."),
        section="Next-event estimation",
        held_out="light density off by a factor of pi"),
]

CATALOGUE["11"] = CHAPTER_11
CATALOGUE["12"] = CHAPTER_12


# ---------------------------------------------------------------- chapter 09

N = "09_random_numbers"
JITTER = "    vec2 pointInPixel = vec2(random01(random), random01(random));\n"
TAUS_X = "tausStep(state.words.x, 13, 19, 12, 4294967294u)"

CHAPTER_09 = [
    Variant(N, "jitter's two numbers drawn the other way round", True, (
        Edit("shaders/trace.comp", JITTER, "    float across = random01(random);\n"
             "    vec2 pointInPixel = vec2(random01(random), across);\n"),)),
    Variant(N, "jitter shifted by half a pixel and wrapped (Cranley-Patterson)", True, (
        Edit("shaders/trace.comp", JITTER, "    vec2 pointInPixel = fract(vec2(random01(random), "
             "random01(random)) + 0.5);\n"),)),
    Variant(N, "generator's four steps XORed in another order", True, (
        Edit("shaders/random.glsl", """    return tausStep(state.words.x, 13, 19, 12, 4294967294u)
         ^ tausStep(state.words.y, 2, 25, 4, 4294967288u)
         ^ tausStep(state.words.z, 3, 11, 17, 4294967280u)
         ^ lcgStep(state.words.w);
""", """    uint bits = lcgStep(state.words.w);
    bits ^= tausStep(state.words.z, 3, 11, 17, 4294967280u);
    bits ^= tausStep(state.words.y, 2, 25, 4, 4294967288u);
    return bits ^ tausStep(state.words.x, 13, 19, 12, 4294967294u);
"""),)),

    Variant(N, "one random number for both coordinates of the jitter", False, (
        Edit("shaders/trace.comp", JITTER, "    float u = random01(random);\n"
             "    vec2 pointInPixel = vec2(u);\n"),),
        explanation=("With one random number for both x and y, every jittered point lies on "
                     "the pixel's diagonal."),
        section="Anti-aliasing: a random point in the pixel"),
    Variant(N, "jitter around the pixel's corner, in [-0.5, 0.5)", False, (
        Edit("shaders/trace.comp", JITTER, "    vec2 pointInPixel = vec2(random01(random), "
             "random01(random)) - 0.5;\n"),),
        explanation=("Jittering in [-0.5, 0.5) instead of [0, 1) shifts the whole picture by "
                     "half a pixel."),
        section="Anti-aliasing: a random point in the pixel"),
    Variant(N, "generator without its LCG", False, (
        Edit("shaders/random.glsl", "         ^ tausStep(state.words.z, 3, 11, 17, 4294967280u)"
             "\n         ^ lcgStep(state.words.w);",
             "         ^ tausStep(state.words.z, 3, 11, 17, 4294967280u);"),),
        explanation=("Hybrid Taus XORs three Tausworthe steps and an LCG; without the LCG the "
                     "stream is another, weaker one."),
        section="A generator per pixel"),
    Variant(N, "generator whose state never advances", False, (
        Edit("shaders/random.glsl", "    return tausStep(state.words.x,",
             "    RandomState copy = state;\n    return tausStep(copy.words.x,"),
        Edit("shaders/random.glsl", "         ^ tausStep(state.words.y,",
             "         ^ tausStep(copy.words.y,"),
        Edit("shaders/random.glsl", "         ^ tausStep(state.words.z,",
             "         ^ tausStep(copy.words.z,"),
        Edit("shaders/random.glsl", "         ^ lcgStep(state.words.w);",
             "         ^ lcgStep(copy.words.w);")),
        explanation=("Stepping a copy leaves the state as it was: every call returns the same "
                     "number, so noise never averages."),
        section="A generator per pixel"),
    Variant(N, "a Tausworthe step with a wrong shift", False, (
        Edit("shaders/random.glsl", TAUS_X, TAUS_X.replace("13, 19, 12", "13, 19, 13")),),
        explanation=("One Tausworthe step shifts by the wrong amount, so the numbers are not "
                     "the generator's stream."),
        section="A generator per pixel"),
]

CATALOGUE["09"] = CHAPTER_09


# ---------------------------------------------------------------- chapter 10

S = "10_scenes"
PIXEL_POINT = "    vec2 pointInPixel = vec2(random01(random), random01(random));\n"
AO_DIRECTION = """    float radius = sqrt(random01(random)), angle = 2.0 * PI * random01(random);
"""
QUAD_INSIDE = "    return a >= 0.0 && a <= 1.0 && b >= 0.0 && b <= 1.0;\n"
PREVIEW = "    return material.emission.rgb + material.albedo.rgb * occlusion;\n"

CHAPTER_10 = [
    Variant(S, "pixel point drawn y first", True, (
        Edit("shaders/trace.comp", PIXEL_POINT, """    float y = random01(random);
    vec2 pointInPixel = vec2(random01(random), y);
"""),)),
    Variant(S, "cosine directions by the angle drawn first", True, (
        Edit("shaders/trace.comp", AO_DIRECTION, """    float angle = 2.0 * PI * random01(random), radius = sqrt(random01(random));
"""),)),
    Variant(S, "quad test by the two edge projections, no dual vectors", True, (
        Edit("shaders/scene.glsl", """    vec3 w = normal / dot(normal, normal);
    float a = dot(w, cross(p, quad.edge2));
    float b = dot(w, cross(quad.edge1, p));
""", """    // Solve p = a edge1 + b edge2 by the 2x2 system of dot products (Cramer).
    float e11 = dot(quad.edge1, quad.edge1), e12 = dot(quad.edge1, quad.edge2);
    float e22 = dot(quad.edge2, quad.edge2), determinant = e11 * e22 - e12 * e12;
    float p1 = dot(p, quad.edge1), p2 = dot(p, quad.edge2);
    float a = (p1 * e22 - p2 * e12) / determinant;
    float b = (p2 * e11 - p1 * e12) / determinant;
"""),)),

    Variant(S, "occlusion directions uniform over the hemisphere", False, (
        Edit("shaders/trace.comp", AO_DIRECTION, """    float height = random01(random);
    float radius = sqrt(1.0 - height * height), angle = 2.0 * PI * random01(random);
"""),
        Edit("shaders/trace.comp", "         + sqrt(max(0.0, 1.0 - radius * radius)) * normal;",
             "         + height * normal;")),
        explanation=("Occlusion rays go in cosine-weighted directions; uniform ones give the "
                     "horizon too much say."),
        section="The preview: glow plus colour times occlusion"),
    Variant(S, "occlusion ignored: albedo everywhere", False, (
        Edit("shaders/trace.comp", PREVIEW,
             "    return material.emission.rgb + material.albedo.rgb;\n"),),
        explanation=("The preview multiplies the albedo by the occlusion; without it corners "
                     "and contact shadows stay bright."),
        section="The preview: glow plus colour times occlusion"),
    Variant(S, "glow left out", False, (
        Edit("shaders/trace.comp", PREVIEW, "    return material.albedo.rgb * occlusion;\n"),),
        explanation=("Each surface's emission belongs in the preview; left out, lamps show "
                     "only their colour times occlusion."),
        section="The preview: glow plus colour times occlusion"),
    Variant(S, "quads twice as large (edge coordinates up to 2)", False, (
        Edit("shaders/scene.glsl", QUAD_INSIDE,
             "    return a >= 0.0 && a <= 2.0 && b >= 0.0 && b <= 2.0;\n"),),
        explanation=("A point is on a quad when both edge coordinates are in [0, 1]; up to 2, "
                     "quads reach twice as far."),
        section="Spheres and quads"),
]

CATALOGUE["10"] = CHAPTER_10

# ---------------------------------------------------------------- chapter 13

B = "13_bvh"
SLAB_PLANES = """    vec3 nearPlanes = mix(boxMin, boxMax, ray.negative);
    vec3 farPlanes = mix(boxMax, boxMin, ray.negative);
    vec3 tNear = (nearPlanes - ray.origin) * ray.inverseDirection;
    vec3 tFar = (farPlanes - ray.origin) * ray.inverseDirection;
"""
SLAB_RETURN = "    return enter <= exit * 1.0000004 ? enter : BVH_MISS;\n"

CHAPTER_13 = [
    Variant(B, "slab test by min and max of each axis's two distances", True, (
        Edit("shaders/bvh_traversal.glsl", SLAB_PLANES, """    vec3 tBoxMin = (boxMin - ray.origin) * ray.inverseDirection;
    vec3 tBoxMax = (boxMax - ray.origin) * ray.inverseDirection;
    vec3 tNear = min(tBoxMin, tBoxMax);
    vec3 tFar = max(tBoxMin, tBoxMax);
"""),)),
    Variant(B, "grazing rays kept by an absolute margin instead of a relative one", True, (
        Edit("shaders/bvh_traversal.glsl", SLAB_RETURN,
             "    return enter <= exit + 1e-5 ? enter : BVH_MISS;\n"),)),
    Variant(B, "entry and exit folded with tMin and tMax last", True, (
        Edit("shaders/bvh_traversal.glsl",
             "    float enter = max(max(tNear.x, tNear.y), max(tNear.z, tMin));\n"
             "    float exit = min(min(tFar.x, tFar.y), min(tFar.z, tMax));\n",
             "    float enter = max(max(max(tNear.x, tNear.y), tNear.z), tMin);\n"
             "    float exit = min(min(min(tFar.x, tFar.y), tFar.z), tMax);\n"),)),

    Variant(B, "slab test that enters every box", False, (
        Edit("shaders/bvh_traversal.glsl", SLAB_RETURN, "    return enter;\n"),),
        explanation=("The slab test never reports a miss, so rays visit boxes they pass "
                     "beside: the right picture, far more work."),
        section="Walking the tree on the GPU"),
    Variant(B, "slab test that ignores the direction's signs", False, (
        Edit("shaders/bvh_traversal.glsl", SLAB_PLANES, """    vec3 tNear = (boxMin - ray.origin) * ray.inverseDirection;
    vec3 tFar = (boxMax - ray.origin) * ray.inverseDirection;
"""),),
        explanation=("For a ray running towards -x the max plane is the near one; ignoring the "
                     "signs, such rays miss boxes."),
        section="Walking the tree on the GPU"),
    Variant(B, "slab test with near and far planes swapped", False, (
        Edit("shaders/bvh_traversal.glsl", SLAB_PLANES,
             SLAB_PLANES.replace("mix(boxMin, boxMax", "mix(boxMax, boxMin", 1)
             .replace("farPlanes = mix(boxMax, boxMin", "farPlanes = mix(boxMin, boxMax")),),
        explanation=("With the near and far planes swapped a ray seems to leave each slab "
                     "before entering it, and misses boxes."),
        section="Walking the tree on the GPU"),
    Variant(B, "slab test that returns where the ray leaves the box", False, (
        Edit("shaders/bvh_traversal.glsl", SLAB_RETURN,
             "    return enter <= exit * 1.0000004 ? exit : BVH_MISS;\n"),),
        explanation=("Returning where the ray leaves the box instead of where it enters prunes "
                     "boxes that hold nearer hits."),
        section="Walking the tree on the GPU"),
]

CATALOGUE["13"] = CHAPTER_13


# ---------------------------------------------------------------- chapter 14

H = "14_bvh_sah"
SAH = """            double cost = options_.nodeCost * box.halfArea() +
                          options_.triangleCost * (left.halfArea() * leftCount +
                                                   rightAreas_[bin] * rightCount);
"""

CHAPTER_14 = [
    Variant(H, "SAH costs divided by the node's area (split and leaf alike)", True, (
        Edit("chapters/bvh.cpp", SAH, """            double cost = options_.nodeCost +
                          options_.triangleCost * (left.halfArea() * leftCount +
                                                   rightAreas_[bin] * rightCount) /
                          box.halfArea();
"""),
        Edit("chapters/bvh.cpp", "const double leafCost = options_.triangleCost * count * "
             "box.halfArea();", "const double leafCost = options_.triangleCost * count;"))),
    Variant(H, "8 bins instead of 16", True, (
        Edit("chapters/bvh.cpp", "    const int binCount = options_.binCount;\n",
             "    const int binCount = options_.binCount / 2;\n"),)),
    Variant(H, "SAH with a node twice as dear", True, (
        Edit("chapters/bvh.cpp", SAH, SAH.replace("options_.nodeCost * box",
                                                  "2.0 * options_.nodeCost * box")),)),

    Variant(H, "SAH without the triangles (a node's cost only)", False, (
        Edit("chapters/bvh.cpp", SAH,
             "            double cost = options_.nodeCost * box.halfArea();\n"),),
        explanation=("With only the node's cost every split costs the same, so the first "
                     "candidate wins and the tree is poor."),
        section="Building the tree with the surface area heuristic"),
    Variant(H, "SAH with each side's count on the other side's area", False, (
        Edit("chapters/bvh.cpp", SAH, SAH.replace("leftCount +", "rightCount +")
             .replace("* rightCount);", "* leftCount);")),),
        explanation=("Each side's triangle count goes with that side's own area; swapped, the "
                     "heuristic prefers bad splits."),
        section="Building the tree with the surface area heuristic"),
    Variant(H, "SAH that counts triangles but forgets the areas", False, (
        Edit("chapters/bvh.cpp", SAH, """            double cost = options_.nodeCost * box.halfArea() +
                          options_.triangleCost * (leftCount + rightCount) *
                                                   box.halfArea();
"""),),
        explanation=("Without the children's areas every split costs the same and never beats "
                     "a leaf: the tree splits blindly."),
        section="Building the tree with the surface area heuristic",
        # Both make every split cost the same: no better than a list, the heat map at its top.
        same_effect="SAH without the triangles (a node's cost only)"),
    Variant(H, "SAH that weighs the areas but forgets the counts", False, (
        Edit("chapters/bvh.cpp", SAH, """            double cost = options_.nodeCost * box.halfArea() +
                          options_.triangleCost * (left.halfArea() + rightAreas_[bin]);
"""),),
        explanation=("Without the triangle counts the heuristic favours small boxes however "
                     "many triangles they hold."),
        section="Building the tree with the surface area heuristic"),
]

CATALOGUE["14"] = CHAPTER_14


# ---------------------------------------------------------------- chapter 15

M = "15_metals"
FRESNEL = """    vec2 n = vec2(eta, k), c = vec2(cosI, 0.0);
    vec2 nSquared = complexMul(n, n);
    vec2 nCosT = complexSqrt(nSquared - vec2(1.0 - cosI * cosI, 0.0));
    vec2 rs = complexDiv(c - nCosT, c + nCosT);
    vec2 rp = complexDiv(complexMul(nSquared, c) - nCosT, complexMul(nSquared, c) + nCosT);
    return 0.5 * (dot(rs, rs) + dot(rp, rp));
"""
# The same reflectance in real arithmetic (pbrt-v3's FrConductor, outside index 1).
FRESNEL_REAL = """    float cos2 = cosI * cosI, sin2 = 1.0 - cos2;
    float t0 = eta * eta - k * k - sin2;
    float a2plusb2 = sqrt(t0 * t0 + 4.0 * eta * eta * k * k);
    float a = sqrt(max(0.0, 0.5 * (a2plusb2 + t0)));
    float t1 = a2plusb2 + cos2, t2 = 2.0 * cosI * a;
    float rs = (t1 - t2) / (t1 + t2);
    float t3 = cos2 * a2plusb2 + sin2 * sin2, t4 = t2 * sin2;
    return 0.5 * (rs + rs * (t3 - t4) / (t3 + t4));
"""
LAMBDA = "    float lambda = 0.5 * (sqrt(1.0 + alpha * alpha * tanSquared) - 1.0);\n"
D_VALUE = "    return 1.0 / (PI * alpha2 * stretched * stretched);\n"

CHAPTER_15 = [
    Variant(M, "conductor Fresnel in real arithmetic (pbrt's form)", True, (
        Edit("shaders/microfacet.glsl", FRESNEL, FRESNEL_REAL),)),
    Variant(M, "G1 as 2 / (1 + sqrt(1 + alpha^2 tan^2))", True, (
        Edit("shaders/microfacet.glsl", LAMBDA + "    return 1.0 / (1.0 + lambda);\n",
             "    return 2.0 / (1.0 + sqrt(1.0 + alpha * alpha * tanSquared));\n"),)),
    Variant(M, "GGX D written with cos^4 and tan^2", True, (
        Edit("shaders/microfacet.glsl", D_VALUE,
             "    float cos2 = m.z * m.z, tan2 = (1.0 - cos2) / cos2;\n"
             "    float b = 1.0 + tan2 / alpha2;\n"
             "    return 1.0 / (PI * alpha2 * cos2 * cos2 * b * b);\n"),)),
    Variant(M, "visible normals with u.x and u.y swapped", True, (
        Edit("shaders/microfacet.glsl", "    vec2 p = squareToDisk(u);\n",
             "    vec2 p = squareToDisk(u.yx);\n"),)),

    Variant(M, "conductor Fresnel with eta and k swapped", False, (
        Edit("shaders/microfacet.glsl", "vec2 n = vec2(eta, k)", "vec2 n = vec2(k, eta)"),),
        explanation=("A metal's complex index is eta + i k; with the two swapped it reflects "
                     "the wrong amount and colour."),
        section="The Fresnel equations of a metal"),
    Variant(M, "the pdf without the reflection's Jacobian 1 / (4 wo.m)", False, (
        Edit("shaders/microfacet.glsl",
             "return visibleNormalPdf(wi, m, alpha) / (4.0 * dot(wo, m));",
             "return visibleNormalPdf(wi, m, alpha);"),),
        explanation=("Without the reflection's Jacobian 1 / (4 wo.m) the pdf is too large, so "
                     "rough metals come out too dark."),
        section="Sampling the visible normals"),
    Variant(M, "the half vector not normalised", False, (
        Edit("shaders/microfacet.glsl", "    vec3 m = normalize(wi + wo);\n    float value",
             "    vec3 m = wi + wo;\n    float value"),),
        explanation=("D, G and F need the half vector normalised; unnormalised, rough "
                     "highlights come out far too dark."),
        section="Rough metals: a sea of tiny mirrors"),
    Variant(M, "Smith's Lambda with alpha where alpha^2 belongs", False, (
        Edit("shaders/microfacet.glsl", LAMBDA,
             LAMBDA.replace("alpha * alpha * tanSquared", "alpha * tanSquared")),),
        explanation=("Smith's Lambda takes alpha^2 tan^2(theta); with alpha instead, rough "
                     "metals are masked too much."),
        section="Rough metals: a sea of tiny mirrors"),
    Variant(M, "GGX D without its 1 / pi", False, (
        Edit("shaders/microfacet.glsl", D_VALUE,
             "    return 1.0 / (alpha2 * stretched * stretched);\n"),),
        explanation=("GGX's D needs its 1/pi for the microfacets' areas to add up; without it "
                     "rough metals are too bright."),
        section="Rough metals: a sea of tiny mirrors"),
    Variant(M, "light after a mirror MIS-weighted as if NEE had looked there", False, (
        Edit("shaders/path.comp", "afterDelta = isDelta(material);", "afterDelta = false;"),),
        explanation=("NEE skips mirrors, so light reached through one counts in full; "
                     "MIS-weighting it darkens lamps in mirrors."),
        section="Delta BSDFs in the path loop"),
    # Held out: the same Lambda (alpha, not alpha^2) in the closed form of G1,
    # 1 / (1 + (sqrt(1 + x) - 1) / 2) = 2 / (1 + sqrt(1 + x)).
    Variant(M, "G1 as 2 / (1 + sqrt(1 + alpha tan^2)): alpha for alpha^2", False, (
        Edit("shaders/microfacet.glsl", LAMBDA + "    return 1.0 / (1.0 + lambda);\n",
             "    return 2.0 / (1.0 + sqrt(1.0 + alpha * tanSquared));\n"),),
        explanation=("Smith's Lambda takes alpha^2 tan^2(theta); with alpha instead, rough "
                     "metals are masked too much."),
        section="Rough metals: a sea of tiny mirrors",
        held_out="Smith's Lambda with alpha where alpha^2 belongs"),
]

CATALOGUE["15"] = CHAPTER_15


# ---------------------------------------------------------------- chapter 16

GL = "16_glass"
DIELECTRIC_AMPLITUDES = """    float rs = (cosIAbs - etaIT * cosTAbs) / (cosIAbs + etaIT * cosTAbs);
    float rp = (etaIT * cosIAbs - cosTAbs) / (etaIT * cosIAbs + cosTAbs);
"""
REFRACTION = """    vec3 alongSurface = wi - dot(wi, m) * m;
    return cosT * m - etaTI * alongSurface;
"""

CHAPTER_16 = [
    Variant(GL, "Fresnel amplitudes with both signs flipped (same squares)", True, (
        Edit("shaders/dielectric.glsl", DIELECTRIC_AMPLITUDES,
             "    float rs = (etaIT * cosTAbs - cosIAbs) / (cosIAbs + etaIT * cosTAbs);\n"
             "    float rp = (cosTAbs - etaIT * cosIAbs) / (etaIT * cosIAbs + cosTAbs);\n"),)),
    Variant(GL, "Fresnel in pbrt's form with eta_i and eta_t", True, (
        Edit("shaders/dielectric.glsl", DIELECTRIC_AMPLITUDES,
             "    float etaI = 1.0, etaT = etaIT;  // relative indices: the same ratios\n"
             "    float rs = (etaI * cosIAbs - etaT * cosTAbs)\n"
             "               / (etaI * cosIAbs + etaT * cosTAbs);\n"
             "    float rp = (etaT * cosIAbs - etaI * cosTAbs)\n"
             "               / (etaT * cosIAbs + etaI * cosTAbs);\n"),)),
    Variant(GL, "refraction by GLSL's refract() about the normal on wi's side", True, (
        Edit("shaders/dielectric.glsl", REFRACTION,
             "    return refract(-wi, dot(wi, m) > 0.0 ? m : -m, etaTI);\n"),)),
    Variant(GL, "the smooth lobe chosen by u < F rather than u <= F", True, (
        Edit("shaders/dielectric.glsl", "if (u <= fresnel.reflectance) return",
             "if (u < fresnel.reflectance) return"),)),

    Variant(GL, "Fresnel with the indices swapped (eta_i / eta_t for eta_t / eta_i)", False, (
        Edit("shaders/dielectric.glsl", "float etaIT = fromOutside ? eta : 1.0 / eta;",
             "float etaIT = fromOutside ? 1.0 / eta : eta;"),),
        explanation=("From outside eta_t / eta_i is eta, from inside 1 / eta; swapped, glass "
                     "bends and reflects inside out."),
        section="How light divides at a boundary"),
    Variant(GL, "Snell's law with eta_t / eta_i: rays bend the wrong way", False, (
        Edit("shaders/dielectric.glsl", REFRACTION,
             REFRACTION.replace("cosT * m - etaTI * alongSurface",
                                "cosT * m - (1.0 / etaTI) * alongSurface")),),
        explanation=("Snell's law shrinks the surface part by eta_i / eta_t; with eta_t / "
                     "eta_i, refracted rays bend the wrong way."),
        section="How light divides at a boundary"),
    Variant(GL, "the refracted direction's surface part not turned round", False, (
        Edit("shaders/dielectric.glsl", REFRACTION,
             REFRACTION.replace("cosT * m - etaTI", "cosT * m + etaTI")),),
        explanation=("The refracted ray's part along the surface must turn round; without "
                     "that, rays go through mirrored."),
        section="How light divides at a boundary"),
    Variant(GL, "no case for total internal reflection (cos theta_t is NaN)", False, (
        Edit("shaders/dielectric.glsl",
             "    if (sinTSquared >= 1.0) return Fresnel(1.0, 0.0, etaIT, etaTI);  "
             "// total reflection\n", ""),),
        explanation=("Past the critical angle no ray gets through; without the total "
                     "reflection case cos(theta_t) is NaN."),
        section="How light divides at a boundary"),
    Variant(GL, "the index not inverted from inside (eta on both sides)", False, (
        Edit("shaders/dielectric.glsl", "float etaIT = fromOutside ? eta : 1.0 / eta;",
             "float etaIT = eta;"),),
        explanation=("Leaving the glass the ratio is 1 / eta; with eta on both sides, rays "
                     "leaving glass bend as if entering it."),
        section="Inside and outside"),
    Variant(GL, "the back of glass black, as an opaque surface's", False, (
        Edit("shaders/path.comp", "bool glass = material.kind == MATERIAL_DIELECTRIC;",
             "bool glass = false;"),),
        explanation=("A ray inside glass reaches the back of its surface; treating that back "
                     "as black ends every path through it."),
        section="Inside and outside"),
    # Held out: the two ratios' names confused, eta_i / eta_t computed as if it were
    # eta_t / eta_i: both ratios come out inverted, as when the indices are swapped.
    Variant(GL, "the two ratios' roles confused (eta_t / eta_i taken for eta_i / eta_t)",
            False, (
        Edit("shaders/dielectric.glsl",
             "    float etaIT = fromOutside ? eta : 1.0 / eta;\n"
             "    float etaTI = 1.0 / etaIT;\n",
             "    float etaTI = fromOutside ? eta : 1.0 / eta;\n"
             "    float etaIT = 1.0 / etaTI;\n"),),
        explanation=("From outside eta_t / eta_i is eta, from inside 1 / eta; swapped, glass "
                     "bends and reflects inside out."),
        section="How light divides at a boundary",
        held_out="Fresnel with the indices swapped (eta_i / eta_t for eta_t / eta_i)"),
]

CATALOGUE["16"] = CHAPTER_16


# ---------------------------------------------------------------- chapter 17

LT = "17_lens_textures"
CONCENTRIC = """    vec2 ab = 2.0 * u - 1.0;
    if (ab == vec2(0.0)) return vec2(0.0);
    float radius, angle;
    if (abs(ab.x) > abs(ab.y)) {
        radius = ab.x;
        angle = 0.5 * QUARTER_TURN * (ab.y / ab.x);
    } else {
        radius = ab.y;
        angle = QUARTER_TURN - 0.5 * QUARTER_TURN * (ab.x / ab.y);
    }
    return radius * vec2(cos(angle), sin(angle));
"""
BLEND = """    vec3 top = mix(texelAt(image, x, y), texelAt(image, x + 1, y), f.x);
    vec3 bottom = mix(texelAt(image, x, y + 1), texelAt(image, x + 1, y + 1), f.x);
    return mix(top, bottom, f.y);
"""
SRGB = "    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);\n"

CHAPTER_17 = [
    Variant(LT, "polar aperture samples, radius sqrt(u1) (uniform, not concentric)", True, (
        Edit("shaders/camera.glsl", CONCENTRIC,
             "    float angle = 4.0 * QUARTER_TURN * u.y;\n"
             "    return sqrt(u.x) * vec2(cos(angle), sin(angle));\n"),)),
    Variant(LT, "concentric map with the square's axes swapped", True, (
        Edit("shaders/camera.glsl", "    vec2 ab = 2.0 * u - 1.0;\n",
             "    vec2 ab = 2.0 * u.yx - 1.0;\n"),)),
    Variant(LT, "bilinear blended down first, then across", True, (
        Edit("shaders/textures.glsl", BLEND,
             "    vec3 left = mix(texelAt(image, x, y), texelAt(image, x, y + 1), f.y);\n"
             "    vec3 right = mix(texelAt(image, x + 1, y), texelAt(image, x + 1, y + 1), f.y);\n"
             "    return mix(left, right, f.x);\n"),)),
    Variant(LT, "sRGB decoded with a lookup table built once", True, (
        Edit("chapters/textures.cpp", SRGB,
             "    static float table[256] = {};\n"
             "    static bool filled = false;\n"
             "    for (int i = 0; !filled && i < 256; ++i) {\n"
             "        float v = float(i) / 255.0f;\n"
             "        table[i] = v <= 0.04045f ? v / 12.92f\n"
             "                                 : std::pow((v + 0.055f) / 1.055f, 2.4f);\n"
             "    }\n"
             "    filled = true;\n"
             "    (void)c;\n"
             "    return table[encoded];\n"),)),

    Variant(LT, "a square aperture", False, (
        Edit("shaders/camera.glsl", CONCENTRIC, "    return 2.0 * u - 1.0;\n"),),
        explanation=("A lens is a disk; using the square's points as they are blurs "
                     "out-of-focus points into squares."),
        section="The aperture's points: the concentric map"),
    Variant(LT, "polar aperture samples with the radius uniform (crowded centre)", False, (
        Edit("shaders/camera.glsl", CONCENTRIC,
             "    float angle = 4.0 * QUARTER_TURN * u.y;\n"
             "    return u.x * vec2(cos(angle), sin(angle));\n"),),
        explanation=("A radius of u instead of sqrt(u) crowds the lens points at its centre, "
                     "so out-of-focus blur is peaked."),
        section="The aperture's points: the concentric map"),
    Variant(LT, "nearest texel instead of bilinear", False, (
        Edit("shaders/textures.glsl", BLEND,
             "    return texelAt(image, int(floor(xy.x + 0.5)), int(floor(xy.y + 0.5)));\n"),),
        explanation=("Textures blend the four nearest texels; taking the nearest texel alone "
                     "makes magnified images blocky."),
        section="Bilinear filtering, and repeat"),
    Variant(LT, "the image upside down (v not turned to rows)", False, (
        Edit("shaders/textures.glsl", "(1.0 - uv.y) * float(image.height)",
             "uv.y * float(image.height)"),),
        explanation=("Image rows run from the top but v from the bottom; without 1 - v the "
                     "texture is upside down."),
        section="Bilinear filtering, and repeat"),
    Variant(LT, "sRGB values not decoded", False, (
        Edit("chapters/textures.cpp", SRGB, "    return c;\n"),),
        explanation=("Image files hold sRGB-encoded values; used without decoding them, "
                     "textures come out too bright."),
        section="From sRGB to linear, once, on the host"),
    # Held out: v kept as (1 - v) but the rows read bottom up in texelAt; bilinear
    # blending of the reversed rows at (1 - v) H - 1/2 is that of the rows at v H - 1/2.
    Variant(LT, "the image's rows read bottom up (upside down, written another way)", False, (
        Edit("shaders/textures.glsl", "    y = (y + height) % height;\n",
             "    y = height - 1 - (y + height) % height;\n"),),
        explanation=("Image rows run from the top but v from the bottom; without 1 - v the "
                     "texture is upside down."),
        section="Bilinear filtering, and repeat",
        held_out="the image upside down (v not turned to rows)"),
]

CATALOGUE["17"] = CHAPTER_17


# ---------------------------------------------------------------- chapter 18

EN = "18_environment"
SEARCH = """    uint low = 0u, high = count;  // the step is in [low, high)
    while (high - low > 1u) {
        uint middle = (low + high) / 2u;
        if (environmentCdf[start + middle] <= u) low = middle; else high = middle;
    }
"""
FIND_STEP = SEARCH + """    float below = environmentCdf[start + low], above = environmentCdf[start + low + 1u];
    float along = above > below ? (u - below) / (above - below) : 0.5;
    return vec2(float(low), clamp(along, 0.0, 1.0));
"""
PER_STERADIAN = """    float sinTheta = sin(PI * v);
    if (sinTheta <= 0.0) return 0.0;
    float perUv = rowChance * columnChance * float(environmentWidth * environmentHeight);
    return perUv / (2.0 * PI * PI * sinTheta);
"""
PIXEL_UV = """    vec2 uv = vec2((column.x + column.y) / float(environmentWidth),
                   (row.x + row.y) / float(environmentHeight));
"""
LOOKUP_V = "u < 0.0 ? u + 1.0 : u, acos(clamp(d.y, -1.0, 1.0)) / PI"

CHAPTER_18 = [
    Variant(EN, "search for the first entry above u, halving a count (upper bound)", True, (
        Edit("shaders/environment.glsl", SEARCH,
             "    uint first = 0u, remaining = count + 1u;  // the first entry > u\n"
             "    while (remaining > 0u) {\n"
             "        uint halfCount = remaining / 2u;\n"
             "        if (environmentCdf[start + first + halfCount] <= u) {\n"
             "            first += halfCount + 1u;\n"
             "            remaining -= halfCount + 1u;\n"
             "        } else {\n"
             "            remaining = halfCount;\n"
             "        }\n"
             "    }\n"
             "    uint low = first - 1u;\n"),)),
    Variant(EN, "a linear search through the steps", True, (
        Edit("shaders/environment.glsl", SEARCH,
             "    uint low = 0u;\n"
             "    while (low + 1u < count && environmentCdf[start + low + 1u] <= u) ++low;\n"),)),
    Variant(EN, "sin(theta) from cos(theta) as sqrt(1 - cos^2)", True, (
        Edit("shaders/environment.glsl", "    float sinTheta = sin(PI * v);\n",
             "    float cosTheta = cos(PI * v);\n"
             "    float sinTheta = sqrt(max(0.0, 1.0 - cosTheta * cosTheta));\n"),)),
    # The point inside the pixel uniform in solid angle (cos(theta) uniform across the
    # row's band), not in (u, v): then the density per steradian is constant over the
    # pixel, its chance over its solid angle. Correct only with both halves changed.
    Variant(EN, "uniform in solid angle inside the pixel, pdf = chance / solid angle", True, (
        Edit("shaders/environment.glsl", PIXEL_UV,
             "    float cosTop = cos(PI * row.x / float(environmentHeight));\n"
             "    float cosBottom = cos(PI * (row.x + 1.0) / float(environmentHeight));\n"
             "    vec2 uv = vec2((column.x + column.y) / float(environmentWidth),\n"
             "                   acos(clamp(mix(cosTop, cosBottom, row.y), -1.0, 1.0)) / PI);\n"),
        Edit("shaders/environment.glsl", PER_STERADIAN,
             "    float cosTop = cos(PI * float(pixel.y) / float(environmentHeight));\n"
             "    float cosBottom = cos(PI * float(pixel.y + 1u) / float(environmentHeight));\n"
             "    float solidAngle = 2.0 * PI / float(environmentWidth) * (cosTop - cosBottom);\n"
             "    return rowChance * columnChance / solidAngle;\n"))),

    Variant(EN, "the pdf per unit of u and v taken per steradian (no sin theta)", False, (
        Edit("shaders/environment.glsl", "    return perUv / (2.0 * PI * PI * sinTheta);\n",
             "    return perUv / (2.0 * PI * PI);\n"),),
        explanation=("A map pixel covers 2 pi^2 sin(theta) du dv steradians; without "
                     "sin(theta) sampled sky light is too bright."),
        section="The pdf: from the map to the sphere"),
    Variant(EN, "the step above the one u falls in (off by one)", False, (
        Edit("shaders/environment.glsl", "    return vec2(float(low), clamp(along, 0.0, 1.0));\n",
             "    return vec2(float(low + 1u), clamp(along, 0.0, 1.0));\n"),),
        explanation=("Returning the step above the one u falls in puts samples a pixel off, "
                     "chosen with their neighbour's chance."),
        section="Two tables"),
    Variant(EN, "the map read upside down (v from the bottom)", False, (
        Edit("shaders/environment.glsl", LOOKUP_V,
             "u < 0.0 ? u + 1.0 : u, 1.0 - acos(clamp(d.y, -1.0, 1.0)) / PI"),),
        explanation=("v = arccos(d_y) / pi runs from the zenith down; measured from the "
                     "bottom, the sky is upside down."),
        section="A latitude-longitude map"),
    Variant(EN, "equal steps instead of the table's (the starter's findStep)", False, (
        Edit("shaders/environment.glsl", FIND_STEP,
             "    return vec2(floor(u * float(count)), fract(u * float(count)));\n"),),
        explanation=("A pixel must be picked by the tables' CDF steps; equal steps pick it "
                     "with another chance than the pdf says."),
        section="Two tables"),
    Variant(EN, "the pdf without the row's chance (the conditional alone)", False, (
        Edit("shaders/environment.glsl",
             "    float perUv = rowChance * columnChance * float(",
             "    float perUv = columnChance * float("),),
        explanation=("A pixel's chance is its row's chance times its column's in that row; the "
                     "column's alone gives a wrong pdf."),
        section="The pdf: from the map to the sphere"),
    # Held out: the direction's y turned round instead of v: acos(-y) / pi = 1 - acos(y) / pi.
    Variant(EN, "the map read upside down (the direction's y negated)", False, (
        Edit("shaders/environment.glsl", LOOKUP_V,
             "u < 0.0 ? u + 1.0 : u, acos(clamp(-d.y, -1.0, 1.0)) / PI"),),
        explanation=("v = arccos(d_y) / pi runs from the zenith down; measured from the "
                     "bottom, the sky is upside down."),
        section="A latitude-longitude map",
        held_out="the map read upside down (v from the bottom)"),
]

CATALOGUE["18"] = CHAPTER_18


# ---------------------------------------------------------------- appendix A1

F = "A1_fragment_passes"
MEAN_UPDATE = "    mean += (radiance - mean) / float(sampleIndex + 1u);\n"
PREVIOUS_MEAN = ("    vec3 mean = sampleIndex == 0u ? vec3(0.0) : "
                 "texelFetch(previousMean, samePixel, 0).rgb;\n")
CARRIED_STATE = ("    RandomState random = RandomState(texelFetch(previousRandom, "
                 "samePixel, 0));\n")

CHAPTER_A1 = [
    Variant(F, "mean updated with mix()", True, (
        Edit("shaders/path.frag", MEAN_UPDATE,
             "    mean = mix(mean, radiance, 1.0 / float(sampleIndex + 1u));\n"),)),
    Variant(F, "mean as the weighted sum of the old mean and the sample", True, (
        Edit("shaders/path.frag", MEAN_UPDATE,
             "    mean = (mean * float(sampleIndex) + radiance) / float(sampleIndex + 1u);\n"),)),

    Variant(F, "the point in the pixel drawn the other way round", True, (
        Edit("shaders/path.frag",
             "    Ray ray = primaryRay(pixel, imageSize, random2(random));",
             "    Ray ray = primaryRay(pixel, imageSize, random2(random).yx);"),)),

    Variant(F, "generator restarted from the seed every pass", False, (
        Edit("shaders/path.frag", CARRIED_STATE,
             "    RandomState random = seedHashed(seed, pixel.y * imageSize.x + pixel.x);\n"),),
        explanation=("The generator's state carries over between passes; reseeded each pass, "
                     "every pass repeats the same sample."),
        section="Accumulating in two framebuffers (ping-pong)"),
    Variant(F, "previous mean left out: the newest sample only", False, (
        Edit("shaders/path.frag", PREVIOUS_MEAN, "    vec3 mean = vec3(0.0);\n"),),
        explanation=("Each pass updates the mean the last pass wrote; from zero it leaves "
                     "sample / n, a picture fading to black."),
        section="Accumulating in two framebuffers (ping-pong)"),
    Variant(F, "generator state not written back: every pass starts as seeded", False, (
        Edit("shaders/path.frag", "    newRandomState = random.words;\n",
             "    newRandomState = texelFetch(previousRandom, samePixel, 0);\n"),),
        explanation=("Writing back the old random state instead of the advanced one repeats "
                     "the same sample every pass."),
        section="Accumulating in two framebuffers (ping-pong)",
        # Both start every pass from the seeded state: the same sample, pass after pass.
        same_effect="generator restarted from the seed every pass"),
    Variant(F, "an exponential average: old mean and new sample half each", False, (
        Edit("shaders/path.frag", MEAN_UPDATE, "    mean = 0.5 * (mean + radiance);\n"),),
        explanation=("A running mean gives the new sample weight 1 / (n + 1); halving each "
                     "time keeps the last few samples' noise."),
        section="Accumulating in two framebuffers (ping-pong)"),
    Variant(F, "previous mean read from the pixel to the right", False, (
        Edit("shaders/path.frag", PREVIOUS_MEAN,
             PREVIOUS_MEAN.replace("samePixel, 0", "samePixel + ivec2(1, 0), 0")),),
        explanation=("Each pixel must read its own previous mean; reading its right "
                     "neighbour's smears the picture sideways."),
        section="Accumulating in two framebuffers (ping-pong)"),
]

CATALOGUE["A1"] = CHAPTER_A1


# ---------------------------------------------------------------- appendix A2

G = "A2_gl33_fragment"
QUAD_READ = ("    return Quad(origin, edge1, edge2, materialOf(indices), "
             "emitterOf(indices.y));\n")
TRIANGLE_READ = ("    vec4 corners = texel(first), normals = texel(first + 1u);\n")

CHAPTER_A2 = [
    Variant(G, "quad's indices texel counted back from the end of its run", True, (
        Edit("shaders/scene.glsl", "    vec4 indices = texel(first + 3u);\n",
             "    vec4 indices = texel(first + uint(QUAD_TEXELS) - 1u);\n"),)),
    Variant(G, "triangle's two texels fetched the other way round", True, (
        Edit("shaders/scene.glsl", TRIANGLE_READ,
             "    vec4 normals = texel(first + 1u);\n    vec4 corners = texel(first);\n"),)),
    Variant(G, "emitter indices rounded to the nearest whole number", True, (
        Edit("shaders/scene.glsl",
             "uint emitterOf(float index) { return index < 0.0 ? NO_EMITTER : uint(index); }",
             "uint emitterOf(float index) {\n"
             "    return index < -0.5 ? NO_EMITTER : uint(index + 0.5);\n}"),)),

    Variant(G, "quad's two edges swapped (its front turned away)", False, (
        Edit("shaders/scene.glsl", QUAD_READ,
             QUAD_READ.replace("origin, edge1, edge2", "origin, edge2, edge1")),),
        explanation=("A quad's front is the side edge1 x edge2 points to; with the edges "
                     "swapped, walls show their black backs."),
        section="Shapes in a buffer texture"),
    Variant(G, "quad's indices read from its first texel (the origin's)", False, (
        Edit("shaders/scene.glsl", "    vec4 indices = texel(first + 3u);\n",
             "    vec4 indices = texel(first);\n"),),
        explanation=("A quad's material and emitter are in its fourth texel; read from the "
                     "first, they are its origin's coordinates."),
        section="Shapes in a buffer texture",
        # All three lose every quad, the lamps with the walls: a black picture.
        same_effect="quad's two edges swapped (its front turned away)"),
    Variant(G, "quads three texels apart instead of four", False, (
        Edit("shaders/scene.glsl", "    uint first = firstQuadTexel + i * uint(QUAD_TEXELS);\n",
             "    uint first = firstQuadTexel + i * uint(QUAD_TEXELS - 1);\n"),),
        explanation=("Each quad takes four texels; stepping by three reads every quad after "
                     "the first from the wrong texels."),
        section="Shapes in a buffer texture",
        # All three lose every quad, the lamps with the walls: a black picture.
        same_effect="quad's two edges swapped (its front turned away)"),
    Variant(G, "triangle's corner and normal texels swapped", False, (
        Edit("shaders/scene.glsl", TRIANGLE_READ,
             "    vec4 corners = texel(first + 1u), normals = texel(first);\n"),),
        explanation=("A triangle's first texel holds its corners' indices, its second its "
                     "normals'; swapped, meshes fall apart."),
        section="Shapes in a buffer texture"),
]

CATALOGUE["A2"] = CHAPTER_A2


# ---------------------------------------------------------------- chapter 22

R = "22_path_regeneration"
REGENERATE = """        done += 1u;  // as chapter 09: the running mean, one sample at a time
        mean += (path.radiance - mean) / float(sampleIndex + done);
        if (done == samplesThisDispatch) return mean;
        path = startPath(cameraRay(pixel, random));  // the next sample, in this lane
"""
NEXT_PATH = "        path = startPath(cameraRay(pixel, random));  // the next sample, in this lane\n"

CHAPTER_22 = [
    Variant(R, "the mean by explicit weights", True, (
        Edit("shaders/path.comp", REGENERATE,
             "        done += 1u;\n"
             "        float n = float(sampleIndex + done);\n"
             "        mean = mean * ((n - 1.0) / n) + path.radiance / n;\n"
             "        if (done == samplesThisDispatch) return mean;\n"
             + NEXT_PATH),)),
    Variant(R, "the count raised inside the test", True, (
        Edit("shaders/path.comp", REGENERATE,
             "        mean += (path.radiance - mean) / float(sampleIndex + done + 1u);\n"
             "        if (++done == samplesThisDispatch) return mean;\n" + NEXT_PATH),)),
    Variant(R, "the next path's state set field by field", True, (
        Edit("shaders/path.comp", NEXT_PATH,
             "        path.ray = cameraRay(pixel, random);\n"
             "        path.radiance = vec3(0.0);\n"
             "        path.throughput = vec3(1.0);\n"
             "        path.directionPdf = 0.0;\n"
             "        path.afterDelta = false;\n"
             "        path.bounce = 0;\n"),)),

    Variant(R, "the finished path's light carried into the next", False, (
        Edit("shaders/path.comp", NEXT_PATH,
             "        vec3 carried = path.radiance;\n" + NEXT_PATH +
             "        path.radiance = carried;\n"),),
        explanation=("A new sample must start with no light; carrying the finished path's "
                     "radiance over counts it again."),
        section="Path regeneration"),
    Variant(R, "the finished path's throughput carried into the next", False, (
        Edit("shaders/path.comp", NEXT_PATH,
             "        vec3 kept = path.throughput;\n" + NEXT_PATH +
             "        path.throughput = kept;\n"),),
        explanation=("The next path must start with a throughput of 1; carrying the finished "
                     "path's over scales its light wrongly."),
        section="Path regeneration"),
    Variant(R, "the bounce count not started again", False, (
        Edit("shaders/path.comp", NEXT_PATH,
             "        int bounces = path.bounce;\n" + NEXT_PATH +
             "        path.bounce = bounces;\n"),),
        explanation=("Each new path counts its bounces from 0; going on with the old count "
                     "cuts later samples short of --depth."),
        section="Path regeneration"),
    Variant(R, "the next path goes on from the last one's ray, not from the camera", False, (
        Edit("shaders/path.comp", NEXT_PATH,
             "        path.radiance = vec3(0.0);\n"
             "        path.bounce = 0;\n"),),
        explanation=("A new sample needs a fresh camera ray and throughput; going on from the "
                     "ended path's ray adds wrong light."),
        section="Path regeneration"),
]

CATALOGUE["22"] = CHAPTER_22


# ---------------------------------------------------------------- chapter 23

W = "23_wavefront"
PUSH = """    uint place = atomicAdd(queues[queue].size, 1u);
    queueItems[queue * poolSize + place] = slot;
"""
GROUPS = "    queues[queue].groupsX = (size + QUEUE_GROUP_SIZE - 1u) / QUEUE_GROUP_SIZE;\n"
CAMERA_DRAWS = """    vec2 inPixel = random2(random);
    Ray ray = primaryRay(pixel, imageSize, inPixel, random2(random));
"""

CHAPTER_23 = [
    # The loop goes on from the size the failed swap saw: re-reading the size instead
    # is wrong, since the buffer is not `coherent` and the compiler may keep the first
    # read (on llvmpipe, the loop then spins until Mesa 22 ends the invocation).
    Variant(W, "a place taken by a compare-and-swap loop", True, (
        Edit("shaders/wavefront.glsl", PUSH,
             "    uint place = queues[queue].size;\n"
             "    for (;;) {\n"
             "        uint seen = atomicCompSwap(queues[queue].size, place, place + 1u);\n"
             "        if (seen == place) break;\n"
             "        place = seen;\n"
             "    }\n"
             "    queueItems[queue * poolSize + place] = slot;\n"),)),
    Variant(W, "one work group for each item: wasteful, but every item runs", True, (
        Edit("shaders/wavefront_dispatch.comp", GROUPS,
             "    queues[queue].groupsX = size;\n"),)),
    Variant(W, "groups by a shift and a remainder", True, (
        Edit("shaders/wavefront_dispatch.comp", GROUPS,
             "    queues[queue].groupsX = size / QUEUE_GROUP_SIZE + "
             "(size % QUEUE_GROUP_SIZE != 0u ? 1u : 0u);\n"),)),
    Variant(W, "the lens point drawn before the pixel point (other noise)", True, (
        Edit("shaders/wavefront_camera.comp", CAMERA_DRAWS,
             "    vec2 onLens = random2(random);\n"
             "    Ray ray = primaryRay(pixel, imageSize, random2(random), onLens);\n"),)),

    Variant(W, "the size read and written back, not atomically", False, (
        Edit("shaders/wavefront.glsl", PUSH,
             "    uint place = queues[queue].size;\n"
             "    queues[queue].size = place + 1u;\n"
             "    queueItems[queue * poolSize + place] = slot;\n"),),
        explanation=("Many invocations push at once; a plain read and write of the size gives "
                     "two one place, and paths are lost."),
        section="The wavefront",
        # A race too: how many paths are lost depends on how the CPU's threads interleave.
        # On an Intel Xeon it matched its signature; on an AMD EPYC (2 cores) the nearest
        # signature was its own, at 1.02 times as far as a match may be.
        recognisable=False),
    Variant(W, "the items written without their queue's offset", False, (
        Edit("shaders/wavefront.glsl", PUSH,
             "    uint place = atomicAdd(queues[queue].size, 1u);\n"
             "    queueItems[place] = slot;\n"),),
        explanation=("Each queue owns poolSize places from queue * poolSize; without that "
                     "offset the queues overwrite each other."),
        section="The wavefront",
        # A race between the queues: which paths survive changes from run to run, and the
        # picture's noise by twenty times between runs of the same code; at the students'
        # seeds it was 1.9 times as far from its signature as a match may be.
        recognisable=False),
    Variant(W, "the place written into the queue instead of the slot", False, (
        Edit("shaders/wavefront.glsl", PUSH,
             "    uint place = atomicAdd(queues[queue].size, 1u);\n"
             "    queueItems[queue * poolSize + place] = place;\n"),),
        explanation=("A queue holds path slot numbers; storing the place instead makes the "
                     "next kernel work on the wrong paths."),
        section="The wavefront"),
    Variant(W, "work groups rounded down", False, (
        Edit("shaders/wavefront_dispatch.comp", GROUPS,
             "    queues[queue].groupsX = size / QUEUE_GROUP_SIZE;\n"),),
        explanation=("Work groups must cover every queued item; rounding their number down "
                     "leaves the last few paths undone."),
        section="Dispatching what the GPU counted"),
]

CATALOGUE["23"] = CHAPTER_23


# ---------------------------------------------------------------- chapter 24

M = "24_participating_media"
CHANNEL = "    int channel = min(int(u.x * 3.0), 2);\n"
MEAN_DENSITY = "    float pdf = (density.r + density.g + density.b) / 3.0;\n"
HG_COSINE = "        cosTheta = (1.0 + g * g - s * s) / (2.0 * g);\n"

CHAPTER_24 = [
    Variant(M, "the channel picked from the end of the random number", True, (
        Edit("shaders/media.glsl", CHANNEL, "    int channel = min(int((1.0 - u.x) * 3.0), 2);\n"),)),
    Variant(M, "the distance drawn from u rather than 1 - u", True, (
        Edit("shaders/media.glsl",
             "-log(1.0 - u.y) / extinction[channel]", "-log(max(u.y, 1e-30)) / extinction[channel]"),)),
    Variant(M, "Henyey-Greenstein sampled with 1 - u", True, (
        Edit("shaders/media.glsl", "        float s = (1.0 - g * g) / (1.0 + g - 2.0 * g * u.x);\n",
             "        float s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u.x);\n"),)),

    Variant(M, "the distance's density of one channel (green) for all three", False, (
        Edit("shaders/media.glsl", MEAN_DENSITY, "    float pdf = density.g;\n"),),
        explanation=("The distance's density is the mean over the three channels; green's "
                     "alone weights red and blue wrongly."),
        section="Where the ray scatters: free-flight sampling"),
    Variant(M, "always red's distance, divided by the mean density", False, (
        Edit("shaders/media.glsl", CHANNEL, "    int channel = 0;\n"),),
        explanation=("Each channel must be drawn a third of the time; always drawing red's "
                     "distance skews the medium's colour."),
        section="Where the ray scatters: free-flight sampling"),
    Variant(M, "scattering weighted by sigma_t instead of sigma_s", False, (
        Edit("shaders/media.glsl",
             "    vec3 kept = flight.scattered ? medium.sigmaS * transmittance : transmittance;\n",
             "    vec3 kept = flight.scattered ? extinction * transmittance : transmittance;\n"),),
        explanation=("At a scattering the weight takes sigma_s, the share that scatters; with "
                     "sigma_t, absorbed light comes back."),
        section="Where the ray scatters: free-flight sampling"),
    Variant(M, "Henyey-Greenstein sampled with g of the other sign", False, (
        Edit("shaders/media.glsl", HG_COSINE,
             "        cosTheta = -(1.0 + g * g - s * s) / (2.0 * g);\n"),),
        explanation=("Sampled with g of the wrong sign, a medium that scatters light onwards "
                     "sends it back, and the reverse."),
        section="The phase function"),
    Variant(M, "every scattering uniform over the sphere, whatever g", False, (
        Edit("shaders/media.glsl", HG_COSINE, "        cosTheta = 1.0 - 2.0 * u.x;\n"),),
        explanation=("Scattered directions must follow Henyey-Greenstein; drawn uniformly, "
                     "every medium scatters as if g were 0."),
        section="The phase function"),
    # Held out: the sampled cosine kept, the frame built about the reversed direction:
    # the cosine with the direction of travel is negated, as for g of the other sign.
    Variant(M, "Henyey-Greenstein sampled about the reversed direction", False, (
        Edit("shaders/media.glsl", "    return basisAround(travelling) *\n",
             "    return basisAround(-travelling) *\n"),),
        explanation=("Sampled with g of the wrong sign, a medium that scatters light onwards "
                     "sends it back, and the reverse."),
        section="The phase function",
        held_out="Henyey-Greenstein sampled with g of the other sign"),
]

CATALOGUE["24"] = CHAPTER_24


# ---------------------------------------------------------------- chapter 25

M = "25_grid_media"
STEP = ("        t -= log(1.0 - random01(random)) / medium.majorant;\n"
        "        if (t >= far) return flight;\n")  # delta tracking's, not ratio tracking's
REAL_COLLISION = "        if (random01(random) * medium.majorant < sigmaT) {\n"
SIGMA_T = ("        float sigmaT = medium.scale * densityAt(medium, ray.origin + t * ray.direction);\n")
LAST_MIX = "    return mix(mix(x00, x10, f.y), mix(x01, x11, f.y), f.z);\n"

CHAPTER_25 = [
    Variant(M, "the corners mixed along z first, then y, then x", True, (
        Edit("shaders/grid.glsl", LAST_MIX,
             "    float z00 = mix(x00, x01, f.z), z10 = mix(x10, x11, f.z);\n"
             "    return mix(z00, z10, f.y);\n"),)),
    Variant(M, "a real collision when u < sigma_t / majorant", True, (
        Edit("shaders/grid.glsl", REAL_COLLISION,
             "        if (random01(random) < sigmaT / medium.majorant) {\n"),)),
    Variant(M, "steps drawn from u rather than 1 - u", True, (
        Edit("shaders/grid.glsl", "log(1.0 - random01(random))",
             "log(max(random01(random), 1e-30))", count=2),)),

    Variant(M, "the nearest cell's density, no interpolation", False, (
        Edit("shaders/grid.glsl", LAST_MIX,
             "    return gridValue(medium, clamp(ivec3(floor(cells + 0.5)), ivec3(0), last));\n"),),
        explanation=("Densities blend trilinearly between cell centres; the nearest cell's "
                     "value alone makes the medium blocky."),
        section="A grid of densities"),
    Variant(M, "a majorant half the densest sigma_t", False, (
        Edit("shaders/grid.glsl", STEP,
             "        t -= log(1.0 - random01(random)) / (0.5 * medium.majorant);\n"
             "        if (t >= far) return flight;\n"),
        Edit("shaders/grid.glsl", REAL_COLLISION,
             "        if (random01(random) * 0.5 * medium.majorant < sigmaT) {\n")),
        explanation=("The majorant must bound sigma_t everywhere; at half the densest value, "
                     "dense parts scatter too little."),
        section="The majorant, and what a walk costs"),
    Variant(M, "the density without the scale", False, (
        Edit("shaders/grid.glsl", SIGMA_T,
             "        float sigmaT = densityAt(medium, ray.origin + t * ray.direction);\n",
             count=2),),
        explanation=("sigma_t is the medium's scale times the grid's density; without the "
                     "scale the medium is too thin or thick."),
        section="A grid of densities"),
    Variant(M, "ratio tracking keeping exp(-sigma_t / majorant) a step", False, (
        Edit("shaders/grid.glsl", "        kept *= 1.0 - sigmaT / medium.majorant;\n",
             "        kept *= exp(-sigmaT / medium.majorant);\n"),),
        explanation=("Ratio tracking keeps 1 - sigma_t / majorant a step; exp(-sigma_t / "
                     "majorant) keeps too much: pale shadows."),
        section="Ratio tracking"),
    Variant(M, "shadow rays by delta tracking: all or nothing (noisier, unbiased)", True, (
        Edit("shaders/grid.glsl", "        kept *= 1.0 - sigmaT / medium.majorant;\n",
             "        if (random01(random) * medium.majorant < sigmaT) return 0.0;\n"),)),
    # Held out: the scale left out on the host (the GPU's scale 1; the majorant, made
    # on the host from the scene's scale, unchanged): sigma_t is the bare density again.
    Variant(M, "the density without the scale (the host passes a scale of 1)", False, (
        Edit("chapters/media.cpp", "    packed.scale = medium.scale;\n",
             "    packed.scale = 1.0f;\n"),),
        explanation=("sigma_t is the medium's scale times the grid's density; without the "
                     "scale the medium is too thin or thick."),
        section="A grid of densities",
        held_out="the density without the scale"),
]

CATALOGUE["25"] = CHAPTER_25


# ---------------------------------------------------------------- chapter 26

I = "26_instances"
TO_OBJECT = "    return Ray(ray.origin * transposed + offset, ray.direction * transposed);\n"
NORMAL_BACK = "    return normalize(transposeOfM(placed) * normal);\n"

CHAPTER_26 = [
    Variant(I, "the map as a matrix on the right: M v written out", True, (
        Edit("shaders/instances.glsl", TO_OBJECT,
             "    mat3 m = transpose(transposed);\n"
             "    return Ray(m * ray.origin + offset, m * ray.direction);\n"),)),
    Variant(I, "the normal as a sum of M's rows", True, (
        Edit("shaders/instances.glsl", NORMAL_BACK,
             "    return normalize(normal.x * placed.objectFromWorld0.xyz +\n"
             "                     normal.y * placed.objectFromWorld1.xyz +\n"
             "                     normal.z * placed.objectFromWorld2.xyz);\n"),)),
    Variant(I, "the normal as a row vector times M", True, (
        Edit("shaders/instances.glsl", NORMAL_BACK,
             "    return normalize(normal * transpose(transposeOfM(placed)));\n"),)),

    Variant(I, "the direction normalised in object space", False, (
        Edit("shaders/instances.glsl", TO_OBJECT,
             "    return Ray(ray.origin * transposed + offset,\n"
             "               normalize(ray.direction * transposed));\n"),),
        explanation=("Normalised in object space, the direction measures t in the object's "
                     "units: scaled instances move."),
        section="Into the object's space"),
    Variant(I, "the offset added to the direction too", False, (
        Edit("shaders/instances.glsl", TO_OBJECT,
             "    return Ray(ray.origin * transposed + offset, ray.direction * transposed + offset);\n"),),
        explanation=("A direction is a vector: the map's offset moves points, never "
                     "directions."),
        section="Into the object's space"),
    Variant(I, "the normal turned by the placement itself", False, (
        Edit("shaders/instances.glsl", NORMAL_BACK,
             "    return normalize(inverse(transpose(transposeOfM(placed))) * normal);\n"),),
        explanation=("Normals go back by the inverse transpose; the placement itself tilts "
                     "them on unevenly scaled instances."),
        section="Normals back to the world"),
    Variant(I, "the normal left in the object's space", False, (
        Edit("shaders/instances.glsl", NORMAL_BACK, "    return normal;\n"),),
        explanation=("A normal found in the object's space must be turned to the world "
                     "before it shades."),
        section="Normals back to the world"),
    # The host's part: the instance's world box left as its object's box, so that an
    # instance away from its object's place is never entered.
    Variant(I, "the instance's box left in the object's space", False, (
        Edit("chapters/instances.cpp",
             "            const glm::vec3 world(worldFromObject * glm::vec4(p, 1.0f));\n",
             "            const glm::vec3 world(p);\n"),),
        explanation=("The top level needs each instance's box in the world: the object's "
                     "corners, placed."),
        section="A tree over the instances"),
]

CATALOGUE["26"] = CHAPTER_26


# ---------------------------------------------------------------- chapter 27

I = "27_motion"
INSTANT = "    pathTime = random01(random);\n"
MOVED_BACK = "    offset -= pathTime * placed.objectMotion.xyz;\n"

CHAPTER_27 = [
    Variant(I, "the instant counted from the shutter's closing", True, (
        Edit("shaders/path.comp", INSTANT, "    pathTime = 1.0 - random01(random);\n"),)),
    Variant(I, "the instant half an interval on, wrapped round", True, (
        Edit("shaders/path.comp", INSTANT,
             "    pathTime = fract(random01(random) + 0.5);\n"),)),
    Variant(I, "the motion taken off the mapped origin", True, (
        Edit("shaders/instances.glsl", MOVED_BACK, ""),
        Edit("shaders/instances.glsl",
             "    return Ray(ray.origin * transposed + offset, ray.direction * transposed);\n",
             "    vec3 origin = ray.origin * transposed + offset;\n"
             "    return Ray(origin - pathTime * placed.objectMotion.xyz,\n"
             "               ray.direction * transposed);\n"),)),

    Variant(I, "every path at the shutter's opening", False, (
        Edit("shaders/path.comp", INSTANT, "    random01(random);\n"),),
        explanation=("Without an instant of its own each path sees the instances where "
                     "they stand when the shutter opens: no blur."),
        section="Each path at its own instant"),
    Variant(I, "the object's space moved the wrong way", False, (
        Edit("shaders/instances.glsl", MOVED_BACK,
             "    offset += pathTime * placed.objectMotion.xyz;\n"),),
        explanation=("An instance that moves forward is found by moving the ray back: "
                     "the object's space goes the other way."),
        section="Each path at its own instant"),
    Variant(I, "instants beyond the shutter's closing", False, (
        Edit("shaders/path.comp", INSTANT, "    pathTime = 2.0 * random01(random);\n"),),
        explanation=("An instant is a share of the interval, 0 to 1: beyond it instances "
                     "leave their swept boxes."),
        section="Each path at its own instant"),
    # The host's parts: the motion in the world's units handed to the object's space,
    # and the top level's boxes not swept.
    Variant(I, "the motion left in the world's units", False, (
        Edit("chapters/instances.cpp",
             "            placed.objectMotion = glm::vec4(glm::mat3(objectFromWorld) * "
             "instance.motion, 0.0f);\n",
             "            placed.objectMotion = glm::vec4(instance.motion, 0.0f);\n"),),
        explanation=("The motion must be mapped into the object's space by M, or a scaled "
                     "instance moves too far."),
        section="Moving in the object's space"),
    Variant(I, "the top level's boxes not swept", False, (
        Edit("chapters/instances.cpp",
             "            placedLow = glm::min(placedLow, placedLow + instance.motion);\n"
             "            placedHigh = glm::max(placedHigh, placedHigh + instance.motion);\n",
             ""),),
        explanation=("A moving instance's box must hold its whole way over the shutter, or "
                     "rays miss it."),
        section="Boxes swept over the interval"),
]

CATALOGUE["27"] = CHAPTER_27
