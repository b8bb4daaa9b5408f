#include "random_dump.h"

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "course/image_file.h"
#include "shared.h"

void dumpRandomNumbers(course::Session& session, int width, int height, int count,
                       const std::string& path) {
    const size_t pixelCount = size_t(width) * size_t(height);
    course::GpuBuffer drawn(pixelCount * size_t(count) * sizeof(uint32_t));
    drawn.bindStorage(DUMP_BINDING);
    course::ShaderProgram& draw = session.loadCompute("draw_random.comp");
    draw.set("imageSize", glm::uvec2(width, height));
    for (int n = 0; n < count; ++n) {
        draw.set("drawIndex", unsigned(n));
        // The previous dispatch's state writes must land before this one reads them.
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        draw.dispatchCovering(width, height);
    }
    std::vector<uint32_t> numbers = drawn.readAll<uint32_t>();
    course::writeFileAtomically(
        path, std::string(reinterpret_cast<const char*>(numbers.data()),
                          numbers.size() * sizeof(uint32_t)));
}
