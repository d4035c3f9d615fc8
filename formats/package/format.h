#pragma once

// The on-disk layout of a .firelook package, format version 1 (docs/package-format.md is the
// byte-level specification; this header is its code form). Every field's byte offset is in a
// comment and pinned by tests/package/format_layout_test.cpp.

#include <bit>
#include <cstddef>
#include <cstdint>

namespace firelook::package {

static_assert(std::endian::native == std::endian::little,
              "The package format is little-endian and read by memcpy; a big-endian host needs byte swaps");

// A four-character code whose bytes, as stored little-endian, spell a, b, c, d.
constexpr uint32_t makeFourCC(char a, char b, char c, char d) {
    return static_cast<uint32_t>(static_cast<unsigned char>(a)) |
           (static_cast<uint32_t>(static_cast<unsigned char>(b)) << 8) |
           (static_cast<uint32_t>(static_cast<unsigned char>(c)) << 16) |
           (static_cast<uint32_t>(static_cast<unsigned char>(d)) << 24);
}

// Only the major version decides compatibility; a minor bump may add sections, codecs or flags
// that an older reader of the same major either skips (optional) or refuses (required).
inline constexpr uint16_t kFormatMajor = 1;
inline constexpr uint16_t kFormatMinor = 1;  // 1.1: optional per-frame fire lights (FLIT)

// PNG-style identifier: a non-ASCII first byte, a name, and CR LF / Ctrl-Z / LF that reveal
// text-mode transfers and 7-bit channels.
inline constexpr unsigned char kIdentifier[8] = {0x89, 'F', 'L', 'K', 0x0D, 0x0A, 0x1A, 0x0A};

// Section data starts at multiples of this, so mapped raw arrays can be used in place
// (cache line, and enough for any SIMD load).
inline constexpr uint64_t kSectionAlignment = 64;

// Frame number of a section that belongs to the whole package rather than to one frame.
inline constexpr uint32_t kNoFrame = 0xFFFFFFFFu;

// Section type of the provenance metadata (UTF-8 JSON text); the container defines it, so every
// reader understands it.
inline constexpr uint32_t kMetadataType = makeFourCC('M', 'E', 'T', 'A');

// Flag bits of IndexEntry::flags. Bits 1..31 are reserved: written as zero, ignored by readers.
inline constexpr uint32_t kSectionRequired = 1u << 0;

enum class Codec : uint32_t {
    Raw = 0,   // stored bytes are the raw bytes
    Zstd = 1,  // stored bytes are one zstd frame that records the raw size
};

struct FormatVersion {
    uint16_t major = 0;
    uint16_t minor = 0;
    friend bool operator==(const FormatVersion&, const FormatVersion&) = default;
};

// Bytes [0, 64) of the file. Written last by the writer (it only knows the index then).
struct FileHeader {
    unsigned char identifier[8];  // offset  0: kIdentifier
    uint16_t version_major;       // offset  8
    uint16_t version_minor;       // offset 10
    uint32_t header_size;         // offset 12: sizeof(FileHeader) = 64
    uint32_t index_entry_size;    // offset 16: sizeof(IndexEntry) = 64
    uint32_t section_count;       // offset 20: number of index entries
    uint64_t index_offset;        // offset 24: where the index starts; 64-aligned; the index ends the file
    uint64_t file_size;           // offset 32: total bytes, so truncation is told from corruption
    uint64_t index_checksum;      // offset 40: XXH3-64 (seed 0) of the index bytes
    uint64_t reserved;            // offset 48: zero
    uint64_t header_checksum;     // offset 56: XXH3-64 (seed 0) of bytes [0, 56) of this header
};
static_assert(sizeof(FileHeader) == 64);

// One entry of the index, which is an array of section_count entries at index_offset.
struct IndexEntry {
    uint32_t type;         // offset  0: fourcc (makeFourCC)
    uint32_t frame;        // offset  4: frame number, or kNoFrame
    uint32_t flags;        // offset  8: bit 0 = required
    uint32_t codec;        // offset 12: Codec
    uint64_t offset;       // offset 16: first stored byte; 64-aligned
    uint64_t stored_size;  // offset 24: bytes in the file
    uint64_t raw_size;     // offset 32: bytes after decoding (== stored_size for Raw)
    uint64_t checksum;     // offset 40: XXH3-64 (seed 0) of the stored bytes
    uint64_t reserved[2];  // offset 48: zero
};
static_assert(sizeof(IndexEntry) == 64);

// A validated index entry as the reader and writer hand it out.
struct SectionInfo {
    uint32_t type = 0;
    uint32_t frame = kNoFrame;
    uint32_t flags = 0;
    Codec codec = Codec::Raw;
    uint64_t offset = 0;
    uint64_t stored_size = 0;
    uint64_t raw_size = 0;
    uint64_t checksum = 0;

    bool required() const { return (flags & kSectionRequired) != 0; }
    friend bool operator==(const SectionInfo&, const SectionInfo&) = default;
};

}  // namespace firelook::package
