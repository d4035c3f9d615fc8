#include "basis/fire_lights.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <stdexcept>

#include "basis/section_bytes.h"
#include "common/error.h"

namespace firelook::basis {
namespace {

constexpr size_t kHeaderBytes = 24;

}  // namespace

FireLightTable emptyFireLightTable(int clusters, int points, int bins, float extinction_scale,
                                   const glm::dvec3& reference) {
    FireLightTable t;
    t.clusters = clusters;
    t.points = points;
    t.bins = bins;
    t.extinction_scale = extinction_scale;
    t.reference.assign(static_cast<size_t>(clusters), reference);
    t.moments.assign(static_cast<size_t>(clusters) * points * bins * kFireLightMoments, 0.0f);
    return t;
}

std::vector<std::byte> encodeFireLights(const FireLightTable& t) {
    std::vector<std::byte> out;
    out.reserve(kHeaderBytes + t.reference.size() * 24 + t.moments.size() * 4);
    putSectionValue<uint32_t>(out, kFireLightsVersion);
    putSectionValue<uint32_t>(out, static_cast<uint32_t>(t.clusters));
    putSectionValue<uint32_t>(out, static_cast<uint32_t>(t.points));
    putSectionValue<uint32_t>(out, static_cast<uint32_t>(t.bins));
    putSectionValue<float>(out, t.extinction_scale);
    putSectionValue<uint32_t>(out, 0);
    for (const glm::dvec3& r : t.reference)
        for (int i = 0; i < 3; ++i) putSectionValue<double>(out, r[i]);
    for (float m : t.moments) putSectionValue<float>(out, m);
    return out;
}

FireLightTable decodeFireLights(std::span<const std::byte> bytes, int points, int bins, const std::string& where) {
    const auto fail = [&](const std::string& what) {
        throw Error(ErrorCode::Corrupt, where + ": fire lights " + what);
    };
    if (bytes.size() < kHeaderBytes) fail("section is " + std::to_string(bytes.size()) + " bytes, too short");
    size_t at = 0;
    const uint32_t version = getSectionValue<uint32_t>(bytes, at);
    if (version != kFireLightsVersion) fail("have an unknown version " + std::to_string(version));
    FireLightTable t;
    const uint32_t clusters = getSectionValue<uint32_t>(bytes, at), p = getSectionValue<uint32_t>(bytes, at), b = getSectionValue<uint32_t>(bytes, at);
    t.extinction_scale = getSectionValue<float>(bytes, at);
    at += 4;
    if (clusters == 0 || clusters > 1024 || (clusters & (clusters - 1)) != 0)
        fail("have " + std::to_string(clusters) + " clusters, not a power of two up to 1024");
    if (p != static_cast<uint32_t>(points) || b != static_cast<uint32_t>(bins))
        fail("are for " + std::to_string(p) + " grid points and " + std::to_string(b) + " bins, the package has " +
             std::to_string(points) + " and " + std::to_string(bins));
    if (!std::isfinite(t.extinction_scale) || t.extinction_scale < 0.0f) fail("have a bad extinction scale");
    t.clusters = static_cast<int>(clusters);
    t.points = points;
    t.bins = bins;
    const size_t values = size_t{clusters} * p * b * kFireLightMoments;
    if (bytes.size() != kHeaderBytes + size_t{clusters} * 24 + values * 4)
        fail("section is " + std::to_string(bytes.size()) + " bytes, expected " +
             std::to_string(kHeaderBytes + size_t{clusters} * 24 + values * 4));
    t.reference.resize(clusters);
    for (glm::dvec3& r : t.reference)
        for (int i = 0; i < 3; ++i) r[i] = getSectionValue<double>(bytes, at);
    t.moments.resize(values);
    std::memcpy(t.moments.data(), bytes.data() + at, values * 4);
    for (const glm::dvec3& r : t.reference)
        if (!std::isfinite(r.x) || !std::isfinite(r.y) || !std::isfinite(r.z)) fail("have a non-finite position");
    for (size_t i = 0; i < values; i += kFireLightMoments) {
        for (int m = 0; m < kFireLightMoments; ++m)
            if (!std::isfinite(t.moments[i + m])) fail("have a non-finite value");
        if (t.moments[i] < 0.0f || t.moments[i + 4] < 0.0f) fail("have a negative power");
    }
    return t;
}

bool validFireLightCount(const FireLightTable& table, int count) {
    return count >= 1 && count <= table.clusters && (count & (count - 1)) == 0;
}

void evaluateFireLights(const FireLightTable& t, const GridWeights& weights, std::span<const Rgb> rbf, int count,
                        FireLight* out) {
    const int group = t.clusters / count;
    for (int light = 0; light < count; ++light) {
        // Summed about the origin in double: the clusters' moments are about their own references.
        glm::dvec3 intensity(0.0), first(0.0), reference_sum(0.0);
        double power = 0.0, second = 0.0;
        for (int c = light * group; c < (light + 1) * group; ++c) {
            glm::dvec3 rgb(0.0);
            double p = 0.0, m2 = 0.0;
            glm::dvec3 m1(0.0);
            for (int k = 0; k < weights.count; ++k) {
                const double w = weights.weight[k];
                if (w == 0.0) continue;
                for (int i = 0; i < t.bins; ++i) {
                    const float* m = t.at(c, weights.point[k], i);
                    const glm::dvec3 ci = glm::dvec3(rbf[i]) * w;
                    const double mean = (ci.x + ci.y + ci.z) / 3.0;  // the position follows the mean channel
                    rgb += ci * static_cast<double>(m[0]);
                    p += mean * m[0];
                    m1 += mean * glm::dvec3(m[1], m[2], m[3]);
                    m2 += mean * m[4];
                }
            }
            const glm::dvec3& r = t.reference[c];
            intensity += rgb;
            power += p;
            first += m1 + p * r;
            second += m2 + 2.0 * glm::dot(r, m1) + p * glm::dot(r, r);
            reference_sum += r;
        }
        FireLight& l = out[light];
        l.intensity = Rgb(glm::max(intensity, glm::dvec3(0.0)));
        if (power > 0.0 && std::isfinite(power)) {
            l.position = first / power;
            l.radius = std::sqrt(std::max(0.0, second / power - glm::dot(l.position, l.position)));
        } else {
            l.position = reference_sum / static_cast<double>(group);
            l.radius = 0.0;
        }
    }
}

}  // namespace firelook::basis
