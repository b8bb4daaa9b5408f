// Textures: an albedo that varies over a surface, looked up at the hit's texture
// coordinates (u, v). Image texels come linear (decoded on the host, textures.cpp);
// a checker is computed where it is looked up.

layout(std430, binding = UVS_BINDING) readonly buffer Uvs { vec2 uvs[]; };
layout(std430, binding = TEXTURES_BINDING) readonly buffer Textures { Texture textures[]; };
layout(std430, binding = TEXELS_BINDING) readonly buffer Texels { vec4 texels[]; };

// --8<-- [start:texel]
// Texel (x, y) of an image, x from its left edge, y from its top row, each within
// -1 .. size: one step past either edge wraps round (repeat).
vec3 texelAt(Texture image, int x, int y) {
    int width = int(image.width), height = int(image.height);
    x = (x + width) % width;
    y = (y + height) % height;
    return texels[image.firstTexel + uint(y * width + x)].rgb;
}
// --8<-- [end:texel]

// --8<-- [start:bilinear]
// The image as a continuous function: texel centres sit at ((x + 0.5) / width,
// 1 - (y + 0.5) / height) in (u, v), v = 0 at the image's bottom as OBJ files mean it;
// between centres, the four nearest texels are blended by how near each is. The image
// repeats beyond [0, 1].
vec3 bilinear(Texture image, vec2 uv) {
    uv = fract(uv);  // repeat
    vec2 xy = vec2(uv.x * float(image.width), (1.0 - uv.y) * float(image.height)) - 0.5;
    vec2 corner = floor(xy);  // the texel centre up and to the left (-1 past the edge)
    vec2 f = xy - corner;     // how far towards the next one, across and down
    int x = int(corner.x), y = int(corner.y);
    vec3 top = mix(texelAt(image, x, y), texelAt(image, x + 1, y), f.x);
    vec3 bottom = mix(texelAt(image, x, y + 1), texelAt(image, x + 1, y + 1), f.x);
    return mix(top, bottom, f.y);
}
// --8<-- [end:bilinear]

// --8<-- [start:checker]
// Squares of two colours, `scale` of each per unit of u and of v: the first colour
// where u and v are both in the first half of their square or both in the second.
vec3 checker(Texture checker, vec2 uv) {
    vec2 square = fract(checker.scale * uv);
    bool secondU = square.x > 0.5, secondV = square.y > 0.5;
    return secondU == secondV ? checker.color0 : checker.color1;
}
// --8<-- [end:checker]

// --8<-- [start:albedo]
// The albedo of a Lambertian material where it was hit.
vec3 albedoAt(Material material, vec2 uv) {
    if (HAS_TEXTURES == 0 || material.textureIndex == NO_TEXTURE) return material.albedo;
    Texture texture = textures[material.textureIndex];
    return texture.kind == TEXTURE_IMAGE ? bilinear(texture, uv) : checker(texture, uv);
}
// --8<-- [end:albedo]
