#include "textures.h"

#include <cmath>

#include "course/error.h"
#include "course/image_read.h"

// --8<-- [start:srgb]
// Image files store sRGB-encoded values: more of the 256 levels go to the darks, where
// the eye tells levels apart. Shading adds and multiplies light, which only makes sense
// on linear values, so the curve is undone once, at load.
float srgbToLinear(uint8_t encoded) {
    float c = float(encoded) / 255.0f;
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}
// --8<-- [end:srgb]

void addTexture(std::vector<gpu::Texture>& textures, std::vector<glm::vec4>& texels,
                const course::SceneTexture& texture) {
    gpu::Texture packed{};
    if (texture.kind == course::TextureKind::Checker) {
        packed.kind = TEXTURE_CHECKER;
        packed.color0 = texture.color0;
        packed.color1 = texture.color1;
        packed.scale = texture.scale;
        textures.push_back(packed);
        return;
    }
    const course::Image8 image = course::readImage8(texture.path);
    if (texels.size() + size_t(image.width) * image.height > (size_t(1) << 31))
        course::fail(course::ExitCode::BadInput,
                     texture.path + ": the scene's images hold more than 2^31 texels");
    packed.kind = TEXTURE_IMAGE;
    packed.firstTexel = uint32_t(texels.size());
    packed.width = uint32_t(image.width);
    packed.height = uint32_t(image.height);
    // --8<-- [start:decode]
    for (size_t i = 0; i < image.rgb.size(); i += 3) {
        glm::vec4 texel(0.0f);
        for (int c = 0; c < 3; ++c)
            texel[c] = texture.linear ? float(image.rgb[i + c]) / 255.0f
                                      : srgbToLinear(image.rgb[i + c]);
        texels.push_back(texel);
    }
    // --8<-- [end:decode]
    textures.push_back(packed);
}
