#include "normals.h"

// --8<-- [start:area_weighted]
std::vector<glm::vec3> areaWeightedNormals(const std::vector<glm::vec3>& positions,
                                           const std::vector<uint32_t>& corners) {
    std::vector<glm::vec3> sums(positions.size(), glm::vec3(0.0f));
    for (size_t i = 0; i + 2 < corners.size(); i += 3) {
        const glm::vec3 p0 = positions[corners[i]], p1 = positions[corners[i + 1]];
        const glm::vec3 p2 = positions[corners[i + 2]];
        // The cross product's length is twice the triangle's area, so summing it
        // unnormalised weighs each triangle by its area: a sliver of a triangle,
        // common where a tessellation squeezes together, hardly moves the average.
        const glm::vec3 face = glm::cross(p1 - p0, p2 - p0);
        sums[corners[i]] += face;
        sums[corners[i + 1]] += face;
        sums[corners[i + 2]] += face;
    }
    for (glm::vec3& sum : sums) {
        const float length = glm::length(sum);
        if (length > 0.0f) sum /= length;
    }
    return sums;
}
// --8<-- [end:area_weighted]
