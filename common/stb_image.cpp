// The one translation unit that compiles stb_image (Debian's libstb-dev, or the pinned
// copy in third_party/stb): PNG and JPEG only, read from files.
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#include <stb/stb_image.h>
