#include "basis/basis_package.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/gtc/packing.hpp>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace firelook::basis {
namespace {

template <typename T>
std::span<const std::byte> bytesOf(const std::vector<T>& values) {
    return std::as_bytes(std::span<const T>(values));
}

template <typename T>
std::vector<T> readArray(const package::PackageReader& reader, uint32_t type, int frame, size_t expected_count) {
    const package::SectionInfo* section = reader.find(type, static_cast<uint32_t>(frame));
    if (!section)
        throw std::runtime_error(reader.file().string() + ": frame " + std::to_string(frame) + " has no " +
                                 std::string(reinterpret_cast<const char*>(&type), 4) + " section");
    const std::vector<std::byte> raw = reader.read(*section);
    if (raw.size() != expected_count * sizeof(T))
        throw std::runtime_error(reader.file().string() + ": frame " + std::to_string(frame) + " section " +
                                 std::string(reinterpret_cast<const char*>(&type), 4) + " holds " +
                                 std::to_string(raw.size()) + " bytes, expected " +
                                 std::to_string(expected_count * sizeof(T)));
    std::vector<T> out(expected_count);
    if (!raw.empty()) std::memcpy(out.data(), raw.data(), raw.size());
    return out;
}

}  // namespace

// Optical depths are stored as IEEE half: the relative error 2^-11 moves alpha by at most
// max(tau e^-tau) * 2^-11 < 2e-4. The sigmoid depths are stored as their flame part
// F = (O_a + O_b) / 2 = integral of rho (1 + f) / 2, which is exactly 0 wherever no flame
// is crossed, so most of it compresses to nothing.
namespace {
// Optical depths are stored as half floats; this is the largest finite one.
constexpr float kLargestDepth = 65504.0f;
float finiteOr(float v, float fallback) { return std::isfinite(v) ? v : fallback; }
}  // namespace

void writeFrameFactors(package::PackageWriter& writer, const FrameFactors& factors) {
    const size_t pixels_count = static_cast<size_t>(std::max(factors.pixels, 0));
    const size_t rank = static_cast<size_t>(std::max(factors.rank, 0));
    const size_t rays_count = factors.depth_density.size();
    if (factors.u_half.size() != pixels_count * rank ||
        factors.svt.size() != static_cast<size_t>(std::max(factors.columns, 0)) * rank || pixels_count == 0 ||
        rays_count == 0 || rays_count % pixels_count != 0 || factors.depth_sigmoid.size() % rays_count != 0)
        throw std::invalid_argument("frame " + std::to_string(factors.frame) +
                                    ": factor sizes do not match pixels, columns and rank");
    const auto frame = static_cast<uint32_t>(factors.frame);
    writer.addSection(kSectionU, frame, bytesOf(factors.u_half));
    writer.addSection(kSectionSVt, frame, bytesOf(factors.svt));
    const size_t rays = factors.depth_density.size();  // footprint samples x pixels
    const size_t thresholds = rays == 0 ? 0 : factors.depth_sigmoid.size() / rays;
    const size_t pixels = static_cast<size_t>(factors.pixels);
    std::vector<uint16_t> depths;
    depths.reserve(rays * (1 + thresholds));
    // A ray deeper than the largest half is scaled down with its flame parts (the smoke/flame
    // split kept): its transmittance exp(-k * 65504) is 0 in float for every k above 0.0016, so
    // alpha is unchanged, and nothing overflows to inf (2F - O_b would then be NaN).
    std::vector<float> scale(rays, 1.0f);
    for (size_t r = 0; r < rays; ++r) {
        const float d = factors.depth_density[r];
        if (!(d <= kLargestDepth)) scale[r] = d > kLargestDepth ? kLargestDepth / d : 0.0f;
        depths.push_back(glm::packHalf1x16(scale[r] > 0.0f ? d * scale[r] : kLargestDepth));
    }
    for (size_t i = 0; i < factors.depth_sigmoid.size(); ++i) {
        const size_t ray = (i / (thresholds * pixels)) * pixels + i % pixels;
        const float flame = 0.5f * (factors.depth_sigmoid[i] + factors.depth_density[ray]) * scale[ray];
        depths.push_back(glm::packHalf1x16(std::clamp(finiteOr(flame, 0.0f), -kLargestDepth, kLargestDepth)));
    }
    writer.addSection(kSectionDepths, frame, bytesOf(depths));
}

std::string makeMetadata(const BakeDescription& description, const std::string& extra_json) {
    nlohmann::ordered_json doc;
    doc["format"] = "firelook-basis";
    doc["version"] = 1;
    doc["bake"] = nlohmann::ordered_json::parse(bakeDescriptionToJson(description));
    if (!extra_json.empty()) {
        const nlohmann::ordered_json extra = nlohmann::ordered_json::parse(extra_json);
        for (const auto& [key, value] : extra.items()) doc[key] = value;
    }
    return doc.dump(2);
}

BasisPackage BasisPackage::open(const std::filesystem::path& file) {
    package::ReaderOptions options;
    options.understood_types = {kSectionU, kSectionSVt, kSectionDepths};
    package::PackageReader reader = package::PackageReader::open(file, options);
    const std::optional<std::string> metadata = reader.metadata();
    if (!metadata) throw std::runtime_error(file.string() + ": package has no metadata (META) section");
    std::string bake_json;
    try {
        const nlohmann::json doc = nlohmann::json::parse(*metadata);
        if (doc.value("format", std::string()) != "firelook-basis")
            throw std::runtime_error("metadata format is not firelook-basis");
        bake_json = doc.at("bake").dump();
    } catch (const std::exception& e) {
        throw std::runtime_error(file.string() + ": invalid metadata: " + e.what());
    }
    BakeDescription description = parseBakeDescription(bake_json, file.string());
    return BasisPackage(std::move(reader), std::move(description), *metadata);
}

FrameFactors BasisPackage::loadFrame(int frame) const {
    const FrameRecord* record = description_.findFrame(frame);
    if (!record) throw std::runtime_error(file().string() + ": no frame " + std::to_string(frame) + " in the package");
    FrameFactors f;
    f.frame = frame;
    f.pixels = description_.pixelCount();
    f.columns = description_.columnCount();
    f.rank = record->rank;
    const size_t pixels = static_cast<size_t>(f.pixels);
    f.u_half = readArray<uint16_t>(reader_, kSectionU, frame, pixels * f.rank);
    f.svt = readArray<float>(reader_, kSectionSVt, frame, static_cast<size_t>(f.columns) * f.rank);
    const size_t thresholds = description_.alpha_thresholds.size();
    const size_t rays = pixels * description_.footprint_samples;
    const std::vector<uint16_t> depths = readArray<uint16_t>(reader_, kSectionDepths, frame, rays * (1 + thresholds));
    f.depth_density.resize(rays);
    // Non-finite halves (packages written before depths were bounded) read as the bounds, so no
    // depth, and no alpha, is ever NaN.
    for (size_t i = 0; i < rays; ++i)
        f.depth_density[i] = std::clamp(finiteOr(glm::unpackHalf1x16(depths[i]), kLargestDepth), 0.0f, kLargestDepth);
    f.depth_sigmoid.resize(rays * thresholds);
    for (size_t i = 0; i < f.depth_sigmoid.size(); ++i) {
        const size_t ray = (i / (thresholds * pixels)) * pixels + i % pixels;
        const float flame = finiteOr(glm::unpackHalf1x16(depths[rays + i]), 0.0f);
        f.depth_sigmoid[i] = 2.0f * flame - f.depth_density[ray];
    }
    return f;
}

}  // namespace firelook::basis
