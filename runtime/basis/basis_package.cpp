#include "basis/basis_package.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/gtc/packing.hpp>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "common/error.h"

namespace firelook::basis {
namespace {

template <typename T>
std::vector<T> readArray(const package::ContainerReader& reader, uint32_t type, int frame, size_t expected_count) {
    const package::SectionInfo* section = reader.find(type, static_cast<uint32_t>(frame));
    if (!section)
        throw Error(ErrorCode::Corrupt,
                    reader.file().string() + ": frame " + std::to_string(frame) + " has no " +
                        std::string(reinterpret_cast<const char*>(&type), 4) + " section");
    const std::vector<std::byte> raw = reader.read(*section);
    if (raw.size() != expected_count * sizeof(T))
        throw Error(ErrorCode::Corrupt, reader.file().string() + ": frame " + std::to_string(frame) +
                                            " section " +
                                            std::string(reinterpret_cast<const char*>(&type), 4) + " holds " +
                                            std::to_string(raw.size()) + " bytes, expected " +
                                            std::to_string(expected_count * sizeof(T)));
    std::vector<T> out(expected_count);
    if (!raw.empty()) std::memcpy(out.data(), raw.data(), raw.size());
    return out;
}

}  // namespace

namespace {
float finiteOr(float v, float fallback) { return std::isfinite(v) ? v : fallback; }

const package::SectionInfo& frameSection(const package::ContainerReader& reader, uint32_t type, int frame) {
    const package::SectionInfo* section = reader.find(type, static_cast<uint32_t>(frame));
    if (!section)
        throw Error(ErrorCode::Corrupt,
                    reader.file().string() + ": frame " + std::to_string(frame) + " has no " +
                        std::string(reinterpret_cast<const char*>(&type), 4) + " section");
    return *section;
}

std::vector<std::byte> readSection(const package::ContainerReader& reader, uint32_t type, int frame) {
    return reader.read(frameSection(reader, type, frame));
}

// Layout 1: U and depths as IEEE half, S V^T as float32, O_a stored as the flame part
// F = (O_a + O_b) / 2 (docs/package-format.md).
FrameFactors loadLayout1(const package::ContainerReader& reader, const BakeDescription& description, int frame,
                         int rank) {
    FrameFactors f = emptyFrameFactors(description, frame, rank);
    const size_t pixels = static_cast<size_t>(f.pixels);
    f.u_half = readArray<uint16_t>(reader, kSectionU, frame, pixels * f.rank);
    f.svt = readArray<float>(reader, kSectionSVt, frame, static_cast<size_t>(f.columns) * f.rank);
    const size_t thresholds = description.alpha_thresholds.size();
    const size_t rays = pixels * description.footprint_samples;
    const std::vector<uint16_t> depths = readArray<uint16_t>(reader, kSectionDepths, frame, rays * (1 + thresholds));
    f.depth_b.resize(rays);
    // Non-finite halves (packages written before depths were bounded) read as the bounds, so no
    // depth, and no alpha, is ever NaN.
    for (size_t i = 0; i < rays; ++i)
        f.depth_b[i] = std::clamp(finiteOr(glm::unpackHalf1x16(depths[i]), kLargestDepth), 0.0f, kLargestDepth);
    f.depth_a.resize(rays * thresholds);
    for (size_t i = 0; i < f.depth_a.size(); ++i) {
        const size_t ray = (i / (thresholds * pixels)) * pixels + i % pixels;
        const float flame = finiteOr(glm::unpackHalf1x16(depths[rays + i]), 0.0f);
        f.depth_a[i] = 2.0f * flame - f.depth_b[ray];
    }
    return f;
}

}  // namespace

StoredFrame writeFrameFactors(package::ContainerWriter& writer, const BakeDescription& description,
                              const FrameFactors& factors, const FrameCodecSettings& settings) {
    return writeEncodedFrame(writer, factors.frame, encodeFrame(description, factors, settings));
}

StoredFrame writeEncodedFrame(package::ContainerWriter& writer, int frame_number, const EncodedFrame& encoded) {
    const auto frame = static_cast<uint32_t>(frame_number);
    StoredFrame stored;
    stored.u_error = encoded.u_error;
    stored.svt_error = encoded.svt_error;
    stored.alpha_bound = encoded.alpha_bound;
    stored.detailed_pixels = encoded.detailed_pixels;
    stored.u_bytes = writer.addSection(kSectionU, frame, encoded.u).stored_size;
    stored.svt_bytes = writer.addSection(kSectionSVt, frame, encoded.svt).stored_size;
    stored.depth_bytes = writer.addSection(kSectionDepths, frame, encoded.depths).stored_size;
    return stored;
}

std::string makeMetadata(const BakeDescription& description, const std::string& extra_json) {
    nlohmann::ordered_json doc;
    doc["format"] = "firelook-basis";
    doc["version"] = kBasisLayoutVersion;
    doc["bake"] = nlohmann::ordered_json::parse(bakeDescriptionToJson(description));
    if (!extra_json.empty()) {
        const nlohmann::ordered_json extra = nlohmann::ordered_json::parse(extra_json);
        for (const auto& [key, value] : extra.items()) doc[key] = value;
    }
    return doc.dump(2);
}

package::ReaderOptions BasisReader::readerOptions() {
    package::ReaderOptions options;
    options.understood_types = {kSectionU, kSectionSVt, kSectionDepths, kSectionFireLights,
                                kSectionFireProbes};
    return options;
}

BasisReader BasisReader::open(const std::filesystem::path& file) {
    return fromReader(package::ContainerReader::open(file, readerOptions()));
}

BasisReader BasisReader::openMemory(std::span<const std::byte> bytes,
                                      package::ContainerReader::MemoryOwnership ownership, const std::string& name) {
    return fromReader(package::ContainerReader::openMemory(bytes, ownership, name, readerOptions()));
}

BasisReader BasisReader::fromReader(package::ContainerReader reader) {
    const std::filesystem::path file = reader.file();
    const std::optional<std::string> metadata = reader.metadata();
    if (!metadata)
        throw Error(ErrorCode::Corrupt, file.string() + ": package has no metadata (META) section");
    std::string bake_json;
    int layout = 1;
    try {
        const nlohmann::json doc = nlohmann::json::parse(*metadata);
        if (doc.value("format", std::string()) != "firelook-basis")
            throw Error(ErrorCode::Corrupt, "metadata format is not firelook-basis");
        layout = doc.value("version", 1);
        if (layout < 1 || layout > kBasisLayoutVersion)
            throw Error(ErrorCode::UnsupportedFeature, "basis layout version " + std::to_string(layout) +
                                                           " is not one this build reads (1 to " +
                                                           std::to_string(kBasisLayoutVersion) + ")");
        bake_json = doc.at("bake").dump();
    } catch (const Error& e) {
        throw Error(e.code(), file.string() + ": invalid metadata: " + e.what());
    } catch (const std::exception& e) {  // nlohmann-json's: the metadata is not the JSON it should be
        throw Error(ErrorCode::Corrupt, file.string() + ": invalid metadata: " + e.what());
    }
    BakeDescription description = parseBakeDescription(bake_json, file.string());
    return BasisReader(std::move(reader), std::move(description), *metadata, layout);
}

const FrameRecord& BasisReader::record(int frame) const {
    const FrameRecord* record = description_.findFrame(frame);
    if (!record)
        throw Error(ErrorCode::NotFound,
                    file().string() + ": no frame " + std::to_string(frame) + " in the package");
    return *record;
}

FrameFactors BasisReader::loadFrame(int frame) const {
    const int rank = record(frame).rank;
    if (layout_version_ == 1) return loadLayout1(reader_, description_, frame, rank);
    const std::vector<std::byte> u = readSection(reader_, kSectionU, frame);
    const std::vector<std::byte> svt = readSection(reader_, kSectionSVt, frame);
    const std::vector<std::byte> depths = readSection(reader_, kSectionDepths, frame);
    return decodeFrame(description_, frame, rank, u, svt, depths, file().string());
}

ResidentFrame BasisReader::loadResidentFrame(int frame, std::pmr::memory_resource* memory,
                                              std::shared_ptr<const DepthTable> table) const {
    ResidentFrame out(memory);
    out.depth_table = std::move(table);
    FrameReadBuffers buffers;
    loadResidentFrame(frame, out, buffers);
    return out;
}

void BasisReader::loadResidentFrame(int frame, ResidentFrame& out, FrameReadBuffers& buffers) const {
    const int rank = record(frame).rank;
    if (layout_version_ == 1) {
        const EncodedFrame e =
            encodeFrame(description_, loadLayout1(reader_, description_, frame, rank), kLayout1Settings);
        decodeResidentFrame(description_, frame, rank, e.u, e.svt, e.depths, file().string(), out);
        return;
    }
    auto section = [&](uint32_t type, package::SectionBuffer& buffer) {
        return reader_.read(frameSection(reader_, type, frame), buffer);
    };
    const std::span<const std::byte> u = section(kSectionU, buffers.u);
    const std::span<const std::byte> svt = section(kSectionSVt, buffers.svt);
    const std::span<const std::byte> depths = section(kSectionDepths, buffers.depths);
    decodeResidentFrame(description_, frame, rank, u, svt, depths, file().string(), out);
}

std::optional<FireLightTable> BasisReader::loadFireLights(int frame) const {
    const package::SectionInfo* section = reader_.find(kSectionFireLights, static_cast<uint32_t>(frame));
    if (!section) return std::nullopt;
    return decodeFireLights(reader_.read(*section), description_.axes.pointCount(), description_.bins.count,
                            file().string() + ": frame " + std::to_string(frame));
}

std::optional<FireProbeTable> BasisReader::loadFireProbes(int frame) const {
    const package::SectionInfo* section = reader_.find(kSectionFireProbes, static_cast<uint32_t>(frame));
    if (!section) return std::nullopt;
    return decodeFireProbes(reader_.read(*section), description_.axes.pointCount(), description_.bins.count,
                            file().string() + ": frame " + std::to_string(frame));
}

}  // namespace firelook::basis
