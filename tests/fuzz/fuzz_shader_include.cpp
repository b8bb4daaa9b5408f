// Fuzzes the shader preprocessor (#include resolution and #line mapping): the input
// is split into a main shader and one included file at the first NUL byte.
#include <string>

#include "course/error.h"
#include "course/shader_source.h"
#include "fuzz_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    size_t split = 0;
    while (split < size && data[split] != 0) ++split;
    writeScratchFile("main.comp", data, split);
    size_t rest = split < size ? size - split - 1 : 0;
    writeScratchFile("a.glsl", data + size - rest, rest);
    try {
        course::ShaderSource source = course::loadShaderSource(scratchFolder(), "main.comp");
        // Whatever the compiler reports, the log translation must cope.
        course::translateShaderLog(source.text, source.shownPaths);
    } catch (const course::Failure&) {
        // A clean, reported failure is the expected outcome for most inputs.
    }
    return 0;
}
