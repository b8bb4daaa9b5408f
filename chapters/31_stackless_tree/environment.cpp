#include "environment.h"

#include <cmath>
#include <string>

#include <glm/trigonometric.hpp>

#include "course/image_read.h"
#include "course/text_file.h"

namespace {

constexpr float kPi = 3.14159265358979f;

// --8<-- [start:cdf]
// The running sum of `weights`, divided by its total: count + 1 numbers from exactly 0
// to exactly 1, appended to `out`. A step as tall as a weight's share means a uniform
// number lands in it with that probability. All zero (a black row): equal steps, so
// that the table stays valid (the marginal never picks such a row).
void appendCdf(const float* weights, int count, std::vector<float>& out) {
    double total = 0.0;
    for (int i = 0; i < count; ++i) total += weights[i];
    double sum = 0.0;
    out.push_back(0.0f);
    for (int i = 1; i < count; ++i) {
        sum += weights[i - 1];
        out.push_back(total > 0.0 ? float(sum / total) : float(i) / float(count));
    }
    out.push_back(1.0f);
}
// --8<-- [end:cdf]

}  // namespace

EnvironmentMap loadEnvironment(const course::SceneFile& scene) {
    EnvironmentMap map;
    if (!scene.hasEnvironment()) return map;
    const course::SceneEnvironment& environment = scene.environment;
    const course::ImageF image = course::readRadianceMap(environment.path);
    map.width = image.width;
    map.height = image.height;
    for (size_t i = 0; i < image.rgb.size(); ++i)
        if (!std::isfinite(image.rgb[i]) || image.rgb[i] < 0.0f) {
            const size_t texel = i / 3;
            course::failAtLine(scene.path, environment.line,
                               "environment " + course::inQuotes(environment.writtenPath) +
                                   ": texel (row " + std::to_string(texel / image.width) +
                                   ", column " + std::to_string(texel % image.width) +
                                   ") is " + (std::isnan(image.rgb[i]) ? "nan"
                                              : std::isinf(image.rgb[i]) ? "inf"
                                                                         : "negative") +
                                   ": a radiance map holds finite values >= 0");
        }
    for (size_t i = 0; i < image.rgb.size(); i += 3)
        map.radiance.push_back(environment.scale *
                               glm::vec4(image.rgb[i], image.rgb[i + 1], image.rgb[i + 2], 0));

    // --8<-- [start:weights]
    // Each pixel's share of the light: its luminance times sin(theta) at its centre,
    // for the pixels of a latitude-longitude map are slivers near the poles (a row
    // covers 2 pi sin(theta) dtheta steradians). Rows, then the columns of each row.
    std::vector<float> weights(size_t(map.width) * map.height), rowWeights(map.height);
    for (int row = 0; row < map.height; ++row) {
        float sinTheta = std::sin(kPi * (float(row) + 0.5f) / float(map.height));
        rowWeights[row] = 0.0f;
        for (int column = 0; column < map.width; ++column) {
            glm::vec3 l(map.radiance[size_t(row) * map.width + column]);
            float luminance = 0.2126f * l.r + 0.7152f * l.g + 0.0722f * l.b;
            weights[size_t(row) * map.width + column] = luminance * sinTheta;
            rowWeights[row] += luminance * sinTheta;
        }
    }
    appendCdf(rowWeights.data(), map.height, map.distributions);  // the marginal
    for (int row = 0; row < map.height; ++row)                    // the conditionals
        appendCdf(&weights[size_t(row) * map.width], map.width, map.distributions);
    // --8<-- [end:weights]
    return map;
}

void addEnvironment(EnvironmentMap& map, const course::SceneFile& scene,
                    bool hasEmittingShapes, std::vector<glm::vec4>& texels,
                    gpu::PathParameters& parameters) {
    parameters.environmentFirstTexel = uint32_t(texels.size());
    texels.insert(texels.end(), map.radiance.begin(), map.radiance.end());
    if (map.distributions.empty()) map.distributions.push_back(0.0f);  // a buffer of one
    parameters.environmentWidth = uint32_t(map.width);
    parameters.environmentHeight = uint32_t(map.height);
    parameters.environmentRotation = glm::radians(scene.environment.rotationYDegrees);
    parameters.environmentChance = !scene.hasEnvironment() ? 0.0f
                                   : hasEmittingShapes      ? ENVIRONMENT_CHANCE
                                                            : 1.0f;
}
