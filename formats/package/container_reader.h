#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "package/format.h"
#include "package/mapped_file.h"

namespace firelook::package {

namespace detail {
struct ZstdDecompressor;
}

// A caller's buffer for repeated reads of sections: the decoded bytes and a zstd context, both
// reused from read to read, so a reader streaming frames allocates nothing once the buffer has
// grown to the largest section. Not shared between threads (use one per thread).
class SectionBuffer {
  public:
    SectionBuffer();
    ~SectionBuffer();
    SectionBuffer(SectionBuffer&&) noexcept;
    SectionBuffer& operator=(SectionBuffer&&) noexcept;

  private:
    friend class ContainerReader;
    std::vector<std::byte> bytes_;
    std::unique_ptr<detail::ZstdDecompressor> zstd_;
};

struct ReaderOptions {
    // Map the file (POSIX mmap) instead of reading it into memory; falls back to reading when the
    // mapping fails. Either way section data is 64-byte aligned in memory. Ignored by openMemory.
    bool memory_map = true;
    // The section types the caller understands (kMetadataType is always understood). Empty means
    // every type, for inspection tools. A section of another type is skipped when optional and
    // makes open() fail with UnsupportedFeature when required.
    std::vector<uint32_t> understood_types;
};

// A validated, read-only package. open() checks the identifier, the version, both header
// checksums, the index (every section 64-aligned, inside the file, in order, not overlapping,
// with sane sizes, no duplicate (type, frame)) before returning. Section data is checked lazily:
// the first read() or mapped() of a section verifies its XXH3-64 checksum (and remembers that it
// passed), so opening a large package touches only its header and index.
//
// The const member functions are safe to call from several threads at once. Move-only; owns the
// mapping, so spans from mapped() live as long as the reader. Every failure throws PackageError
// naming the file. A mapped file must not be modified in place while open (ContainerWriter never
// does: it replaces files by rename).
class ContainerReader {
  public:
    using MemoryOwnership = detail::MemoryOwnership;

    static ContainerReader open(const std::filesystem::path& file, const ReaderOptions& options = {});
    // A package held in memory (an engine's own archive), with exactly the checks and errors of
    // open(); `name` stands for the file in every message and in file(). Borrow: the bytes are used
    // in place and must stay valid and unchanged for the reader's life, and must be 64-byte aligned
    // (else InvalidArgument, before anything is read); Copy: copied into an aligned buffer now, any
    // alignment.
    static ContainerReader openMemory(std::span<const std::byte> bytes, MemoryOwnership ownership,
                                    const std::filesystem::path& name, const ReaderOptions& options = {});

    ContainerReader(ContainerReader&&) noexcept = default;
    ContainerReader& operator=(ContainerReader&&) noexcept = default;

    FormatVersion version() const { return version_; }
    const std::filesystem::path& file() const { return file_; }  // or openMemory's name
    uint64_t fileSize() const { return file_bytes_.bytes().size(); }
    bool isMemoryMapped() const { return file_bytes_.isMemoryMapped(); }
    bool isBorrowed() const { return file_bytes_.isBorrowed(); }  // openMemory with Borrow

    // The usable sections in file order. Optional sections this reader does not understand (unknown
    // type or codec, e.g. from a newer minor version) are omitted; skippedSectionCount() counts them.
    std::span<const SectionInfo> sections() const { return sections_; }
    std::size_t skippedSectionCount() const { return skipped_count_; }

    // The section with this type and frame, or null. O(log n).
    const SectionInfo* find(uint32_t type, uint32_t frame = kNoFrame) const;

    // The decoded bytes of a section of this reader (InvalidArgument for any other SectionInfo),
    // checksum-verified, with the decoded length checked against the index.
    std::vector<std::byte> read(const SectionInfo& section) const;
    // The same into `buffer`; the span is valid until the buffer's next use.
    std::span<const std::byte> read(const SectionInfo& section, SectionBuffer& buffer) const;

    // The section's bytes as stored (compressed or not), checksum-verified, zero-copy: what
    // ContainerWriter::addStoredSection copies into another package.
    std::span<const std::byte> stored(const SectionInfo& section) const;

    // A zero-copy, 64-byte aligned view of a Raw section (InvalidArgument for Zstd), checksum-verified.
    std::span<const std::byte> mapped(const SectionInfo& section) const;

    // The text of the kMetadataType section, if the package has one.
    std::optional<std::string> metadata() const;

  private:
    ContainerReader() = default;
    // The checks shared by open() and openMemory(), on bytes already held.
    static ContainerReader validated(std::filesystem::path name, detail::MappedFile bytes,
                                   const ReaderOptions& options);
    std::size_t indexOf(const SectionInfo& section, const char* operation) const;
    std::span<const std::byte> verifiedStoredBytes(std::size_t index) const;

    std::filesystem::path file_;
    detail::MappedFile file_bytes_;
    FormatVersion version_;
    std::vector<SectionInfo> sections_;
    std::vector<uint32_t> lookup_order_;             // indices into sections_, sorted by (type, frame)
    std::unique_ptr<std::atomic<bool>[]> verified_;  // per section: checksum already matched
    std::size_t skipped_count_ = 0;
};

}  // namespace firelook::package
