#include "basis/basis_package.h"

#include <cstring>
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

void writeFrameFactors(package::PackageWriter& writer, const FrameFactors& factors) {
    const auto frame = static_cast<uint32_t>(factors.frame);
    writer.addSection(kSectionU, frame, bytesOf(factors.u_half));
    writer.addSection(kSectionSVt, frame, bytesOf(factors.svt));
    std::vector<float> depths = factors.depth_density;
    depths.insert(depths.end(), factors.depth_sigmoid.begin(), factors.depth_sigmoid.end());
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
    std::vector<float> depths =
        readArray<float>(reader_, kSectionDepths, frame,
                         pixels * description_.footprint_samples * (1 + description_.alpha_thresholds.size()));
    const size_t density_count = pixels * description_.footprint_samples;
    f.depth_density.assign(depths.begin(), depths.begin() + density_count);
    f.depth_sigmoid.assign(depths.begin() + density_count, depths.end());
    return f;
}

}  // namespace firelook::basis
