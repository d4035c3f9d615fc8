// Reading and writing the baked basis in a .firelook package: which sections
// hold what (docs/package-format.md, "Baked basis layout"). The container
// itself (checksums, zstd, atomic writes) is formats/package.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <span>
#include <string>

#include "basis/bake_description.h"
#include "basis/fire_lights.h"
#include "basis/fire_probes.h"
#include "basis/frame_codec.h"
#include "basis/frame_factors.h"
#include "package/container_reader.h"
#include "package/container_writer.h"

namespace firelook::basis {

inline constexpr uint32_t kSectionU = package::makeFourCC('U', 'F', 'A', 'C');          // U, half, per frame
inline constexpr uint32_t kSectionSVt = package::makeFourCC('S', 'V', 'T', 'F');        // S V^T, float, per frame
inline constexpr uint32_t kSectionDepths = package::makeFourCC('O', 'D', 'E', 'P');     // optical depths, per frame

// The basis layout this code writes (META "version"): 2 = the frame codec (frame_codec.h).
// Layout 1 (U and depths as IEEE half, S V^T as float32) is still read.
inline constexpr int kBasisLayoutVersion = 2;

// How a layout-1 frame becomes resident: alpha within 2^-15 of the depth grid's range (its
// finest), every ray that differs kept, U and S V^T within 1e-5 of the basis.
inline constexpr FrameCodecSettings kLayout1Settings{1e-6, 0.0, 1e-5};

// What storing one frame chose and cost.
struct StoredFrame {
    double u_error = 0.0, svt_error = 0.0, alpha_bound = 0.0;  // see EncodedFrame
    size_t detailed_pixels = 0;
    uint64_t u_bytes = 0, svt_bytes = 0, depth_bytes = 0;  // in the file, after zstd
    uint64_t bytes() const { return u_bytes + svt_bytes + depth_bytes; }
};

// Encodes one frame (frame_codec.h) and adds its three sections.
StoredFrame writeFrameFactors(package::ContainerWriter& writer, const BakeDescription& description,
                              const FrameFactors& factors, const FrameCodecSettings& settings = {});
// Adds the three sections of a frame already encoded.
StoredFrame writeEncodedFrame(package::ContainerWriter& writer, int frame, const EncodedFrame& encoded);

// The META document: {"format": "firelook-basis", "bake": <description>, ...extra}.
// `extra_json` is a JSON object whose members are added beside "bake" (provenance, errors).
std::string makeMetadata(const BakeDescription& description, const std::string& extra_json);

// Buffers for reading one frame's three sections, reused from frame to frame (one per thread).
struct FrameReadBuffers {
    package::SectionBuffer u, svt, depths;
};

class BasisReader {
public:
    // Throws firelook::Error (package::PackageError's codes, Corrupt, NotFound) naming the file.
    static BasisReader open(const std::filesystem::path& file);
    // The same from a package held in memory (package::ContainerReader::openMemory: a borrowed buffer
    // must be 64-byte aligned and outlive the BasisReader unchanged); `name` stands for the file.
    static BasisReader openMemory(std::span<const std::byte> bytes, package::ContainerReader::MemoryOwnership ownership,
                                   const std::string& name);

    const BakeDescription& description() const { return description_; }
    const std::string& metadataJson() const { return metadata_; }
    const std::filesystem::path& file() const { return reader_.file(); }  // or openMemory's name
    const package::ContainerReader& reader() const { return reader_; }
    int layoutVersion() const { return layout_version_; }
    // Decompresses and validates one frame (sizes against the description).
    FrameFactors loadFrame(int frame) const;
    // The same frame in the resident form (frame_codec.h, decodeResidentFrame). A layout-1 frame
    // is first stored through the frame codec at its finest settings (kLayout1Settings).
    ResidentFrame loadResidentFrame(int frame, std::pmr::memory_resource* memory,
                                    std::shared_ptr<const DepthTable> table = nullptr) const;
    // The same into `out`, reusing its buffers and depth table and `buffers` for the sections
    // (frame_codec.h): what a streaming runtime does, with no allocation once warm.
    void loadResidentFrame(int frame, ResidentFrame& out, FrameReadBuffers& buffers) const;
    // The frame's fire lights (fire_lights.h), or nothing when the package has none for it (packages
    // baked before them). Throws a Corrupt Error naming the file and frame for a damaged section.
    std::optional<FireLightTable> loadFireLights(int frame) const;
    // The frame's fire probes (fire_probes.h), or nothing when the package has none for it.
    std::optional<FireProbeTable> loadFireProbes(int frame) const;

private:
    const FrameRecord& record(int frame) const;  // throws naming the file when there is no such frame
    // What open() and openMemory() share: the reader's options and the META checks.
    static package::ReaderOptions readerOptions();
    static BasisReader fromReader(package::ContainerReader reader);

    BasisReader(package::ContainerReader reader, BakeDescription description, std::string metadata, int layout)
        : reader_(std::move(reader)), description_(std::move(description)), metadata_(std::move(metadata)),
          layout_version_(layout) {}

    package::ContainerReader reader_;
    BakeDescription description_;
    std::string metadata_;
    int layout_version_ = kBasisLayoutVersion;
};

}  // namespace firelook::basis
