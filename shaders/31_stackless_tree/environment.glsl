// The environment light: a latitude-longitude radiance map infinitely far away, the
// background and a light (python_prototypes/sky.py's orientation). Its radiance is in
// the texel buffer (textures.glsl) at environmentFirstTexel; pixel (row, column) is
// the constant radiance of the patch u in [column, column + 1] / width, v in
// [row, row + 1] / height. Needs PI (sampling.glsl).

layout(std430, binding = ENVIRONMENT_CDF_BINDING) readonly buffer EnvironmentCdf {
    float environmentCdf[];  // the marginal over rows, then each row's conditional
};

bool hasEnvironment() { return HAS_ENVIRONMENT != 0 && environmentWidth > 0u; }

// The map turns counter-clockwise (seen from above) by environmentRotation: a world
// direction is looked up turned back by as much.
vec3 turnAboutY(vec3 d, float angle) {
    float c = cos(angle), s = sin(angle);
    return vec3(c * d.x + s * d.z, d.y, -s * d.x + c * d.z);
}

// --8<-- [start:lookup]
// Map coordinates (u, v) of a unit world direction, and back.
vec2 environmentUv(vec3 direction) {
    vec3 d = turnAboutY(direction, -environmentRotation);
    float u = atan(d.x, -d.z) / (2.0 * PI);
    return vec2(u < 0.0 ? u + 1.0 : u, acos(clamp(d.y, -1.0, 1.0)) / PI);
}
vec3 environmentDirection(vec2 uv) {
    float phi = 2.0 * PI * uv.x, theta = PI * uv.y;
    vec3 d = vec3(sin(phi) * sin(theta), cos(theta), -cos(phi) * sin(theta));
    return turnAboutY(d, environmentRotation);
}

ivec2 environmentPixel(vec2 uv) {  // (column, row)
    return min(ivec2(uv * vec2(environmentWidth, environmentHeight)),
               ivec2(environmentWidth, environmentHeight) - 1);
}

// The radiance arriving from infinitely far along `direction` (unit).
vec3 environmentRadiance(vec3 direction) {
    ivec2 pixel = environmentPixel(environmentUv(direction));
    uint texel = environmentFirstTexel + uint(pixel.y) * environmentWidth + uint(pixel.x);
    return texels[texel].rgb;
}
// --8<-- [end:lookup]

// --8<-- [start:pdf]
// How likely the tables make a pixel: its step in the marginal times its step in its
// row's conditional. Spread evenly over the pixel's (u, v) patch, that is width x height
// times as dense per unit of u and v; a patch du dv covers 2 pi^2 sin(theta) du dv
// steradians, so per steradian the density is divided by that.
uint conditionalStart(uint row) {  // where a row's conditional CDF starts
    return environmentHeight + 1u + row * (environmentWidth + 1u);
}

float pixelPdf(uvec2 pixel, float v) {
    float rowChance = environmentCdf[pixel.y + 1u] - environmentCdf[pixel.y];
    uint start = conditionalStart(pixel.y);
    float columnChance = environmentCdf[start + pixel.x + 1u] - environmentCdf[start + pixel.x];
    float sinTheta = sin(PI * v);
    if (sinTheta <= 0.0) return 0.0;
    float perUv = rowChance * columnChance * float(environmentWidth * environmentHeight);
    return perUv / (2.0 * PI * PI * sinTheta);
}

float environmentPdf(vec3 direction) {
    vec2 uv = environmentUv(direction);
    return pixelPdf(uvec2(environmentPixel(uv)), uv.y);
}
// --8<-- [end:pdf]

// --8<-- [start:sample]
// The step of a CDF (count + 1 numbers from `start`) that u falls in, by binary search,
// and where in it: (the step's index, the fraction of the way through it).
vec2 findStep(uint start, uint count, float u) {
    uint low = 0u, high = count;  // the step is in [low, high)
    while (high - low > 1u) {
        uint middle = (low + high) / 2u;
        if (environmentCdf[start + middle] <= u) low = middle; else high = middle;
    }
    float below = environmentCdf[start + low], above = environmentCdf[start + low + 1u];
    float along = above > below ? (u - below) / (above - below) : 0.5;
    return vec2(float(low), clamp(along, 0.0, 1.0));
}

// A direction towards the environment, chosen in proportion to its pixels' weights:
// u.x picks the row through the marginal, u.y the column through that row's
// conditional, each landing somewhere inside the pixel. The pixel's radiance comes
// with it: looked up again from the direction, float rounding would now and then find
// the neighbouring pixel, whose radiance this pdf does not match (a dark pixel next to
// the sun, read as the sun: a firefly).
vec3 sampleEnvironment(vec2 u, out float pdf, out vec3 radiance) {
    vec2 row = findStep(0u, environmentHeight, u.x);
    vec2 column = findStep(conditionalStart(uint(row.x)), environmentWidth, u.y);
    vec2 uv = vec2((column.x + column.y) / float(environmentWidth),
                   (row.x + row.y) / float(environmentHeight));
    uvec2 pixel = uvec2(column.x, row.x);
    pdf = pixelPdf(pixel, uv.y);
    radiance = texels[environmentFirstTexel + pixel.y * environmentWidth + pixel.x].rgb;
    return environmentDirection(uv);
}
// --8<-- [end:sample]
