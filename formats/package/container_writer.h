#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string_view>

#include "package/format.h"

namespace firelook::package {

struct WriterOptions {
    int zstd_level = 10;  // any level zstd accepts (negative = faster); checked by the constructor
    // The minor version written to the header. Only tests of forward compatibility change it.
    uint16_t format_minor = kFormatMinor;
};

// Writes a package one section at a time. Sections stream to a temporary file next to the
// destination, so memory holds one (compressed) section and the index, never the whole package.
// commit() writes the index and header, then fsyncs and renames over the destination atomically
// (common/atomic_file.h):
// readers see either the old file or the complete new one. Destroyed without commit (an exception,
// unwinding after Ctrl-C), the writer deletes its temporary file and leaves the destination alone.
// A process killed outright leaves the temporary, named ".<name>.<pid>-<n>.tmp" beside it.
//
// Deterministic: the same sections in the same order with the same zstd level and zstd library
// give identical bytes; nothing time- or host-dependent is stored.
//
// Not thread-safe; move-only. Every failure throws PackageError naming the destination.
class ContainerWriter {
  public:
    // Creates the temporary file (IoError if the folder is missing or not writable).
    explicit ContainerWriter(std::filesystem::path destination, WriterOptions options = {});
    ~ContainerWriter();
    ContainerWriter(ContainerWriter&&) noexcept;
    ContainerWriter& operator=(ContainerWriter&&) noexcept;  // first discards this writer's uncommitted file

    // Appends one section; `raw` may be empty. A (type, frame) pair may appear once
    // (InvalidArgument otherwise). `required` tells readers that do not understand `type` to refuse
    // the package rather than skip the section. After an I/O failure the writer refuses further use.
    SectionInfo addSection(uint32_t type, uint32_t frame, std::span<const std::byte> raw,
                           Codec codec = Codec::Zstd, bool required = true);

    // Appends a section of another package as it is stored there (`section` its index entry,
    // `stored` its stored bytes, e.g. ContainerReader::stored): no decompression or recompression, so
    // a merge of packages keeps every section's bytes. The checksum is verified against `section`
    // (Corrupt otherwise); the same (type, frame) rule as addSection.
    SectionInfo addStoredSection(const SectionInfo& section, std::span<const std::byte> stored);

    // The provenance record: UTF-8 JSON text (not parsed here; its content is the baker's business),
    // stored as section kMetadataType, kNoFrame, zstd-compressed.
    SectionInfo addMetadata(std::string_view json);

    // Publishes the package. Afterwards the writer accepts no more calls (InvalidState).
    void commit();

    const std::filesystem::path& destination() const;
    const std::filesystem::path& temporaryPath() const;

  private:
    struct Impl;
    Impl& impl(const char* operation) const;
    std::unique_ptr<Impl> impl_;
};

// The bytes addSection stores for a section (Codec::Zstd at `options`' level), without writing
// anything: a bake that aims at a package size (baker/bake/storage_target.h) compares candidate
// encodings of a frame by what they would cost in the file. Not thread-safe; one per thread.
class StoredSizeMeter {
  public:
    explicit StoredSizeMeter(WriterOptions options = {});
    ~StoredSizeMeter();
    StoredSizeMeter(StoredSizeMeter&&) noexcept;
    StoredSizeMeter& operator=(StoredSizeMeter&&) noexcept;

    uint64_t storedBytes(std::span<const std::byte> raw);

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace firelook::package
