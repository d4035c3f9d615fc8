// Fuzz target: bytes -> a .firelook file -> ContainerReader (every section read) -> BasisReader
// (every frame loaded and rendered with the package's default look).
//
// Three ways an input is used, so that mutations get past the checksums:
//   1. The bytes as they are (a real package, truncated or flipped: checksum and layout checks).
//   2. If they start with the package identifier, the same bytes with every checksum recomputed
//      (header, index, each section whose range lies in the file): exercises the index and zstd
//      validation, and BasisReader on corrupt but "valid" data.
//   3. Otherwise the bytes are "META JSON text, NUL, payload": a correct package is written with
//      ContainerWriter from that metadata, each frame's U / SVt / ODEP section filled from the payload
//      to the size the description asks for (so frames load and render with arbitrary floats,
//      NaN and Inf included). The payload's first byte picks the codec and whether sizes are exact.
//
// Contract checked: every failure is a std::exception whose message names the file; a rendered
// image has no NaN/Inf and alpha in [0, 1].
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <vector>

#define XXH_INLINE_ALL
#include <xxhash.h>

#include "basis/basis_package.h"
#include "basis/look_renderer.h"
#include "fuzz_support.h"
#include "look/look.h"
#include "package/error.h"
#include "package/container_reader.h"
#include "package/container_writer.h"

namespace {

using namespace firelook;
constexpr const char* kTarget = "fuzz_package_reader";
// Bigger sections or images than this are not written or rendered: the harness tests logic, not RAM.
constexpr std::size_t kMaxBytes = std::size_t{8} << 20;

void checkNamesFile(const std::exception& e, const std::filesystem::path& file) {
    if (!fuzz::contains(e.what(), file.filename().string()))
        fuzz::fail(kTarget, std::string("error does not name the file: ") + e.what());
}

// Loads every frame the description lists; renders the small ones with the package's default look.
void loadAndRenderFrames(const basis::BasisReader& package) {
    const basis::BakeDescription& d = package.description();
    // Bounded work: the harness does not render a huge image or fit hundreds of bins.
    const bool render = !d.default_look_json.empty() && double(d.width) * d.height <= 4096.0 && d.bins.count <= 256;
    Look look;
    bool have_look = false;
    if (render) {
        try {
            look = parseLook(d.default_look_json, package.file().string());
            have_look = true;
        } catch (const LookError& e) {
            checkNamesFile(e, package.file());
        }
    }
    for (const basis::FrameRecord& record : d.frames) {
        basis::ResidentFrame frame;
        try {
            frame = package.loadResidentFrame(record.frame, std::pmr::get_default_resource());
        } catch (const std::exception& e) {
            checkNamesFile(e, package.file());
            continue;
        }
        if (!have_look) continue;
        std::vector<float> rgba(static_cast<std::size_t>(d.pixelCount()) * 4, -1.0f);
        try {
            basis::renderLookImage(d, frame, look, rgba);
        } catch (const LookError& e) {
            checkNamesFile(e, package.file());
            continue;
        }
        for (std::size_t i = 0; i < rgba.size(); ++i) {
            if (!std::isfinite(rgba[i])) fuzz::fail(kTarget, "non-finite value in the rendered image");
            if (i % 4 == 3 && !(rgba[i] >= 0.0f && rgba[i] <= 1.0f)) fuzz::fail(kTarget, "alpha outside [0, 1]");
            if (rgba[i] < 0.0f) fuzz::fail(kTarget, "negative radiance in the rendered image");
        }
    }
}

void exercise(const std::filesystem::path& file) {
    for (const bool map : {true, false}) {
        try {
            package::ReaderOptions options;
            options.memory_map = map;
            const package::ContainerReader reader = package::ContainerReader::open(file, options);
            for (const package::SectionInfo& section : reader.sections()) {
                try {
                    if (section.raw_size > kMaxBytes) continue;
                    const std::vector<std::byte> bytes = reader.read(section);
                    if (bytes.size() != section.raw_size) fuzz::fail(kTarget, "read() size differs from the index");
                    if (section.codec == package::Codec::Raw) {
                        const auto view = reader.mapped(section);
                        if (view.size() != bytes.size() ||
                            (!bytes.empty() && std::memcmp(view.data(), bytes.data(), bytes.size()) != 0))
                            fuzz::fail(kTarget, "mapped() differs from read()");
                    }
                } catch (const package::PackageError& e) {
                    checkNamesFile(e, file);
                }
            }
            try {
                (void)reader.metadata();
            } catch (const package::PackageError& e) {
                checkNamesFile(e, file);
            }
        } catch (const package::PackageError& e) {
            checkNamesFile(e, file);
        }
    }
    try {
        const basis::BasisReader package = basis::BasisReader::open(file);
        loadAndRenderFrames(package);
    } catch (const std::exception& e) {
        checkNamesFile(e, file);
    }
}

// Mode 2: recompute every checksum a reader checks, where the header and index make that possible.
std::vector<std::uint8_t> withChecksumsFixed(std::vector<std::uint8_t> bytes) {
    if (bytes.size() < sizeof(package::FileHeader)) return bytes;
    package::FileHeader header;
    std::memcpy(&header, bytes.data(), sizeof header);
    const uint64_t index_bytes = uint64_t{header.section_count} * sizeof(package::IndexEntry);
    if (header.index_offset <= bytes.size() && index_bytes <= bytes.size() - header.index_offset) {
        for (uint32_t i = 0; i < header.section_count; ++i) {
            std::uint8_t* at = bytes.data() + header.index_offset + uint64_t{i} * sizeof(package::IndexEntry);
            package::IndexEntry entry;
            std::memcpy(&entry, at, sizeof entry);
            if (entry.offset <= bytes.size() && entry.stored_size <= bytes.size() - entry.offset) {
                entry.checksum = XXH3_64bits(bytes.data() + entry.offset, entry.stored_size);
                std::memcpy(at, &entry, sizeof entry);
            }
        }
        header.index_checksum = XXH3_64bits(bytes.data() + header.index_offset, index_bytes);
    }
    header.header_checksum = XXH3_64bits(&header, offsetof(package::FileHeader, header_checksum));
    std::memcpy(bytes.data(), &header, sizeof header);
    return bytes;
}

// Mode 3: a well-formed container around fuzzed metadata and payload.
void writeStructured(const std::filesystem::path& file, const std::uint8_t* data, std::size_t size) {
    const auto* nul = static_cast<const std::uint8_t*>(std::memchr(data, 0, size));
    const std::size_t json_size = nul ? static_cast<std::size_t>(nul - data) : size;
    const std::string json(reinterpret_cast<const char*>(data), json_size);
    const std::uint8_t* payload = nul ? nul + 1 : data + size;
    const std::size_t payload_size = static_cast<std::size_t>(data + size - payload);
    const std::uint8_t flags = payload_size > 0 ? payload[0] : 0;
    const package::Codec codec = (flags & 1) ? package::Codec::Raw : package::Codec::Zstd;
    const bool exact_sizes = (flags & 2) == 0;

    package::ContainerWriter writer(file, package::WriterOptions{1});
    writer.addMetadata(json);
    // Which frames and sizes the description asks for, if it parses at all.
    std::vector<std::pair<int, std::array<std::size_t, 3>>> frames;
    try {
        const nlohmann::json doc = nlohmann::json::parse(json);
        const basis::BakeDescription d = basis::parseBakeDescription(doc.at("bake").dump(), "fuzz");
        for (const basis::FrameRecord& r : d.frames) {
            if (frames.size() >= 4) break;
            const double pixels = double(d.width) * d.height;
            const double sizes[3] = {pixels * r.rank * 2.0, double(d.axes.pointCount()) * d.columnsPerPoint() * r.rank * 4.0,
                                     pixels * (1.0 + d.alpha_thresholds.size()) * 4.0};
            std::array<std::size_t, 3> bytes{};
            for (int s = 0; s < 3; ++s)
                bytes[s] = sizes[s] >= 0.0 && sizes[s] <= double(kMaxBytes) ? static_cast<std::size_t>(sizes[s]) : 0;
            frames.push_back({r.frame, bytes});
        }
    } catch (const std::exception&) {
    }
    std::size_t cursor = payload_size > 0 ? 1 : 0;
    const uint32_t types[3] = {basis::kSectionU, basis::kSectionSVt, basis::kSectionDepths};
    std::vector<std::byte> section;
    std::vector<uint64_t> written;
    for (const auto& [frame, bytes] : frames) {
        const uint64_t key = static_cast<uint32_t>(frame);
        if (std::find(written.begin(), written.end(), key) != written.end()) continue;
        written.push_back(key);
        for (int s = 0; s < 3; ++s) {
            std::size_t n = bytes[s];
            if (!exact_sizes && cursor < payload_size) n = payload[cursor++] % (n + 9);
            section.assign(n, std::byte{0});
            for (std::size_t i = 0; i < n && payload_size > 0; ++i) {
                section[i] = std::byte{payload[cursor % payload_size]};
                ++cursor;
            }
            writer.addSection(types[s], static_cast<uint32_t>(frame), section, codec);
        }
    }
    writer.commit();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::filesystem::path file = fuzz::scratchFolder() / "input.firelook";
    const bool is_package = size >= sizeof package::kIdentifier &&
                            std::memcmp(data, package::kIdentifier, sizeof package::kIdentifier) == 0;
    if (is_package || size < 2) {
        fuzz::writeBytes(file, data, size);
        exercise(file);
        if (is_package) {
            const std::vector<std::uint8_t> fixed = withChecksumsFixed(std::vector<std::uint8_t>(data, data + size));
            fuzz::writeBytes(file, fixed.data(), fixed.size());
            exercise(file);
        }
    } else {
        fuzz::writeBytes(file, data, size);  // not a package: NotAPackage, naming the file
        exercise(file);
        writeStructured(file, data, size);
        exercise(file);
    }
    return 0;
}
