// Textures as the shaders read them: a table of gpu::Texture (shared.h) and, for image
// textures, their texels one after another in one buffer, already linear.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "course/scene_file.h"
#include "shared.h"

// 8-bit sRGB-encoded value -> linear fraction: the inverse of the curve PNGs are
// written with (course::linearToSrgb).
float srgbToLinear(uint8_t encoded);

// Appends the texture to `textures`; an image's texels (read with stb_image, exit code
// 3 if it cannot be) go to the end of `texels`, top row first, decoded from sRGB to
// linear unless the scene file says `linear`.
void addTexture(std::vector<gpu::Texture>& textures, std::vector<glm::vec4>& texels,
                const course::SceneTexture& texture);
