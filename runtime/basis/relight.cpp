#include "basis/relight.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <stdexcept>
#include <string>

#include "common/error.h"

namespace firelook::basis {

glm::dvec3 checkedUnitDirection(const RunTimeLight& light) {
    const double length = glm::length(light.direction);
    if (!std::isfinite(length) || !(length > 0.0))
        throw Error(ErrorCode::InvalidArgument, "the light direction must be finite and non-zero");
    for (int c = 0; c < 3; ++c)
        if (!std::isfinite(light.irradiance[c]) || light.irradiance[c] < 0.0f)
            throw Error(ErrorCode::InvalidArgument, "the light's irradiance must be finite and >= 0");
    return light.direction / length;
}

std::array<double, kSixWayLightCount> relightWeights(std::span<const glm::dvec3, kSixWayLightCount> six_way,
                                                     const glm::dvec3& direction, double exponent) {
    if (!(exponent > 0.0))
        throw Error(ErrorCode::InvalidArgument, "the relighting exponent must be positive");
    const glm::dvec3 d = checkedUnitDirection({direction, Rgb(0.0f)});
    std::array<double, kSixWayLightCount> w{};
    double sum = 0.0;
    for (int i = 0; i < kSixWayLightCount; ++i) {
        w[i] = std::pow(std::max(0.0, glm::dot(d, six_way[i])), exponent);
        sum += w[i];
    }
    // Six directions of three opposite pairs: some cosine is at least 1/sqrt(3), so sum > 0.
    for (double& x : w) x /= sum;
    return w;
}

namespace {

void requireRelightLights(const BakeDescription& d, const std::string& package_name) {
    if (d.relightFirstLight() < 0)
        throw Error(
            ErrorCode::InvalidArgument,
            package_name +
                ": baked without six-way or sphere lights; a light direction chosen at run time needs a "
                "bake with --lights six-way or --lights sphere");
}

}  // namespace

std::vector<double> packageRelightWeights(const BakeDescription& d, const glm::dvec3& direction,
                                          const std::string& package_name) {
    requireRelightLights(d, package_name);
    if (d.six_way_first_light >= 0) {
        const std::span<const glm::dvec3, kSixWayLightCount> six_way(
            d.light_directions.data() + d.six_way_first_light, kSixWayLightCount);
        const std::array<double, kSixWayLightCount> w = relightWeights(six_way, direction);
        return {w.begin(), w.end()};
    }
    // Unit directions: the barycentric coefficients' sum bound (sphereWeights) needs them.
    std::vector<glm::dvec3> sphere;
    for (int i = 0; i < d.sphere_light_count; ++i) {
        const glm::dvec3& t = d.light_directions[static_cast<size_t>(d.sphere_first_light + i)];
        const double length = glm::length(t);
        if (!std::isfinite(length) || !(length > 0.0))
            throw Error(ErrorCode::InvalidArgument,
                        package_name + ": sphere light " + std::to_string(i) + " has no direction");
        sphere.push_back(t / length);
    }
    try {
        return sphereWeights(sphere, d.sphere_triangles, direction);
    } catch (const Error& e) {
        throw Error(e.code(), package_name + ": " + e.what());
    }
}

std::vector<Rgb> relightIrradiance(const BakeDescription& d, std::span<const RunTimeLight> lights,
                                   const std::string& package_name) {
    requireRelightLights(d, package_name);
    std::vector<Rgb> out(static_cast<size_t>(d.relightLightCount()), Rgb(0.0f));
    for (const RunTimeLight& light : lights) {
        const glm::dvec3 direction = checkedUnitDirection(light);
        const std::vector<double> w = packageRelightWeights(d, direction, package_name);
        for (size_t i = 0; i < out.size(); ++i) out[i] += static_cast<float>(w[i]) * light.irradiance;
    }
    // Each light's share is at most its own irradiance, but a sum of huge ones can overflow; an
    // infinite irradiance would give NaN where a column is 0.
    for (const Rgb& e : out)
        if (!std::isfinite(e.r) || !std::isfinite(e.g) || !std::isfinite(e.b))
            throw Error(ErrorCode::InvalidArgument,
                        package_name + ": the lights' irradiances add up past the float range");
    return out;
}

void applyRunTimeLights(const BakeDescription& d, std::span<const RunTimeLight> lights,
                        const std::string& package_name, std::span<Rgb> light_irradiance) {
    const std::vector<Rgb> columns = relightIrradiance(d, lights, package_name);
    if (light_irradiance.size() != d.light_directions.size())
        throw Error(ErrorCode::InvalidArgument,
                    package_name + ": " + std::to_string(light_irradiance.size()) +
                        " light irradiances for " + std::to_string(d.light_directions.size()) + " lights");
    std::copy(columns.begin(), columns.end(), light_irradiance.begin() + d.relightFirstLight());
}

void applyRunTimeLight(const BakeDescription& d, const RunTimeLight& light, const std::string& package_name,
                       std::span<Rgb> light_irradiance) {
    applyRunTimeLights(d, std::span<const RunTimeLight>(&light, 1), package_name, light_irradiance);
}

}  // namespace firelook::basis
