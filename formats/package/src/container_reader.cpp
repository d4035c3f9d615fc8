#include "package/container_reader.h"

#include <algorithm>
#include <cstring>
#include <new>
#include <unordered_set>
#include <utility>

#include "checksum.h"
#include "package/error.h"
#include "section_name.h"
#include "zstd_codec.h"

namespace firelook::package {
namespace {

bool sameKey(const SectionInfo& a, const SectionInfo& b) { return a.type == b.type && a.frame == b.frame; }

bool keyLess(const SectionInfo& a, const SectionInfo& b) {
    return a.type != b.type ? a.type < b.type : a.frame < b.frame;
}

std::string bytesText(uint64_t count) { return std::to_string(count) + " bytes"; }

// Checks the header and the index's integrity before anything in them is trusted. Order matters:
// the identifier says whether this is a package at all, the major version whether the rest of the
// header is laid out as we know, the header checksum whether its fields are intact; only then does
// the declared file size separate truncation from corruption.
FileHeader validatedHeader(std::span<const std::byte> bytes, const std::filesystem::path& file) {
    if (bytes.empty()) throw PackageError(ErrorCode::NotAPackage, file, "the file is empty");
    const std::size_t identifier_bytes = std::min(bytes.size(), sizeof kIdentifier);
    if (std::memcmp(bytes.data(), kIdentifier, identifier_bytes) != 0) {
        throw PackageError(ErrorCode::NotAPackage, file,
                           "it does not start with the FireLook package identifier");
    }
    // The identifier and major version keep their place in every major version, and a newer major
    // may have a different header size, so the major is judged before the header's length.
    if (bytes.size() >= offsetof(FileHeader, version_minor)) {
        uint16_t major = 0;
        std::memcpy(&major, bytes.data() + offsetof(FileHeader, version_major), sizeof major);
        if (major > kFormatMajor) {
            throw PackageError(ErrorCode::NewerMajorVersion, file,
                               "written in format major version " + std::to_string(major) +
                                   "; this reader supports major version " + std::to_string(kFormatMajor));
        }
        if (major < kFormatMajor) {
            throw PackageError(ErrorCode::Corrupt, file,
                               "format major version " + std::to_string(major) + " never existed");
        }
    }
    if (bytes.size() < sizeof(FileHeader)) {
        throw PackageError(ErrorCode::Truncated, file,
                           "the file has " + bytesText(bytes.size()) + ", fewer than the 64-byte header");
    }
    FileHeader header;
    std::memcpy(&header, bytes.data(), sizeof header);
    const auto header_bytes = bytes.first(offsetof(FileHeader, header_checksum));
    if (detail::checksum64(header_bytes) != header.header_checksum) {
        throw PackageError(ErrorCode::Corrupt, file, "header checksum mismatch");
    }
    if (header.header_size != sizeof(FileHeader) || header.index_entry_size != sizeof(IndexEntry)) {
        throw PackageError(ErrorCode::Corrupt, file,
                           "header size " + std::to_string(header.header_size) + " and index entry size " +
                               std::to_string(header.index_entry_size) +
                               " differ from 64 of format version 1");
    }
    if (bytes.size() < header.file_size) {
        throw PackageError(ErrorCode::Truncated, file,
                           "the file has " + bytesText(bytes.size()) + " but its header declares " +
                               bytesText(header.file_size));
    }
    if (bytes.size() > header.file_size) {
        throw PackageError(ErrorCode::Corrupt, file,
                           "the file has " + bytesText(bytes.size()) + " but its header declares only " +
                               bytesText(header.file_size));
    }
    const uint64_t index_size = uint64_t{header.section_count} * sizeof(IndexEntry);
    if (header.index_offset < sizeof(FileHeader) || header.index_offset % kSectionAlignment != 0 ||
        header.index_offset > header.file_size || header.file_size - header.index_offset != index_size) {
        throw PackageError(ErrorCode::Corrupt, file,
                           "the index of " + std::to_string(header.section_count) + " entries at offset " +
                               std::to_string(header.index_offset) + " does not end the " +
                               bytesText(header.file_size) + " file");
    }
    if (detail::checksum64(bytes.subspan(header.index_offset, index_size)) != header.index_checksum) {
        throw PackageError(ErrorCode::Corrupt, file, "index checksum mismatch");
    }
    return header;
}

// Checks one entry's place and sizes; `data_end` is where the previous section's bytes ended.
void validateEntry(const IndexEntry& entry, uint64_t data_end, uint64_t index_offset,
                   const std::filesystem::path& file) {
    const std::string name = detail::sectionName(entry.type, entry.frame);
    if (entry.offset % kSectionAlignment != 0) {
        throw PackageError(
            ErrorCode::Corrupt, file,
            name + " starts at offset " + std::to_string(entry.offset) + ", not a multiple of 64");
    }
    if (entry.offset < data_end || entry.offset > index_offset ||
        entry.stored_size > index_offset - entry.offset) {
        throw PackageError(ErrorCode::Corrupt, file,
                           name + " (" + bytesText(entry.stored_size) + " at offset " +
                               std::to_string(entry.offset) +
                               ") overlaps the header, another section or the index");
    }
    if (entry.codec == static_cast<uint32_t>(Codec::Raw) && entry.raw_size != entry.stored_size) {
        throw PackageError(ErrorCode::Corrupt, file,
                           name + " is raw but its raw size " + std::to_string(entry.raw_size) +
                               " differs from its stored size " + std::to_string(entry.stored_size));
    }
    if (entry.codec == static_cast<uint32_t>(Codec::Zstd) &&
        entry.raw_size > detail::maxZstdRawSize(entry.stored_size)) {
        throw PackageError(ErrorCode::Corrupt, file,
                           name + " claims " + bytesText(entry.raw_size) + " from " +
                               bytesText(entry.stored_size) + " of zstd, more than zstd can encode");
    }
}

}  // namespace

ContainerReader ContainerReader::open(const std::filesystem::path& file, const ReaderOptions& options) {
    return validated(file, detail::MappedFile::open(file, options.memory_map), options);
}

ContainerReader ContainerReader::openMemory(std::span<const std::byte> bytes, MemoryOwnership ownership,
                                        const std::filesystem::path& name, const ReaderOptions& options) {
    return validated(name, detail::MappedFile::fromMemory(bytes, ownership, name), options);
}

ContainerReader ContainerReader::validated(std::filesystem::path name, detail::MappedFile held,
                                       const ReaderOptions& options) {
    ContainerReader reader;
    reader.file_ = std::move(name);
    reader.file_bytes_ = std::move(held);
    const std::filesystem::path& file = reader.file_;
    const std::span<const std::byte> bytes = reader.file_bytes_.bytes();
    const FileHeader header = validatedHeader(bytes, file);
    reader.version_ = FormatVersion{header.version_major, header.version_minor};

    const auto understood = [&](uint32_t type) {
        return options.understood_types.empty() || type == kMetadataType ||
               std::find(options.understood_types.begin(), options.understood_types.end(), type) !=
                   options.understood_types.end();
    };

    std::unordered_set<uint64_t> keys;
    uint64_t data_end = sizeof(FileHeader);
    for (uint32_t i = 0; i < header.section_count; ++i) {
        IndexEntry entry;
        std::memcpy(&entry, bytes.data() + header.index_offset + uint64_t{i} * sizeof(IndexEntry),
                    sizeof entry);
        validateEntry(entry, data_end, header.index_offset, file);
        data_end = entry.offset + entry.stored_size;
        const std::string name = detail::sectionName(entry.type, entry.frame);
        if (!keys.insert((uint64_t{entry.type} << 32) | entry.frame).second) {
            throw PackageError(ErrorCode::Corrupt, file, name + " appears twice in the index");
        }

        const bool known_codec = entry.codec == static_cast<uint32_t>(Codec::Raw) ||
                                 entry.codec == static_cast<uint32_t>(Codec::Zstd);
        if (!known_codec || !understood(entry.type)) {
            if ((entry.flags & kSectionRequired) != 0) {
                throw PackageError(
                    ErrorCode::UnsupportedFeature, file,
                    name + " is required but " +
                        (known_codec ? std::string("its type is not understood by this reader")
                                     : "its codec " + std::to_string(entry.codec) + " is unknown") +
                        " (format version " + std::to_string(header.version_major) + "." +
                        std::to_string(header.version_minor) + ")");
            }
            ++reader.skipped_count_;
            continue;
        }
        reader.sections_.push_back(SectionInfo{entry.type, entry.frame, entry.flags,
                                               static_cast<Codec>(entry.codec), entry.offset,
                                               entry.stored_size, entry.raw_size, entry.checksum});
    }

    reader.lookup_order_.resize(reader.sections_.size());
    for (uint32_t i = 0; i < reader.lookup_order_.size(); ++i) reader.lookup_order_[i] = i;
    std::sort(reader.lookup_order_.begin(), reader.lookup_order_.end(),
              [&](uint32_t a, uint32_t b) { return keyLess(reader.sections_[a], reader.sections_[b]); });
    reader.verified_ = std::make_unique<std::atomic<bool>[]>(reader.sections_.size());
    return reader;
}

const SectionInfo* ContainerReader::find(uint32_t type, uint32_t frame) const {
    SectionInfo key;
    key.type = type;
    key.frame = frame;
    const auto found = std::lower_bound(
        lookup_order_.begin(), lookup_order_.end(), key,
        [&](uint32_t index, const SectionInfo& wanted) { return keyLess(sections_[index], wanted); });
    if (found == lookup_order_.end() || !sameKey(sections_[*found], key)) return nullptr;
    return &sections_[*found];
}

std::size_t ContainerReader::indexOf(const SectionInfo& section, const char* operation) const {
    // Only offsets that open() validated are ever used: a SectionInfo must be one of ours, or equal to one.
    if (!sections_.empty() && &section >= sections_.data() &&
        &section < sections_.data() + sections_.size()) {
        return static_cast<std::size_t>(&section - sections_.data());
    }
    const SectionInfo* ours = find(section.type, section.frame);
    if (ours == nullptr || !(*ours == section)) {
        throw PackageError(ErrorCode::InvalidArgument, file_,
                           std::string(operation) + ": " + detail::sectionName(section.type, section.frame) +
                               " is not a section of this package");
    }
    return static_cast<std::size_t>(ours - sections_.data());
}

std::span<const std::byte> ContainerReader::verifiedStoredBytes(std::size_t index) const {
    const SectionInfo& section = sections_[index];
    const std::span<const std::byte> stored =
        file_bytes_.bytes().subspan(section.offset, section.stored_size);
    if (!verified_[index].load(std::memory_order_acquire)) {
        if (detail::checksum64(stored) != section.checksum) {
            throw PackageError(ErrorCode::Corrupt, file_,
                               detail::sectionName(section.type, section.frame) + ": checksum mismatch");
        }
        verified_[index].store(true, std::memory_order_release);
    }
    return stored;
}

std::vector<std::byte> ContainerReader::read(const SectionInfo& section) const {
    const std::size_t index = indexOf(section, "read");
    const SectionInfo& ours = sections_[index];
    const std::span<const std::byte> stored = verifiedStoredBytes(index);
    if (ours.codec == Codec::Zstd) {
        return detail::zstdDecompress(stored, ours.raw_size, file_,
                                      detail::sectionName(ours.type, ours.frame));
    }
    try {
        return std::vector<std::byte>(stored.begin(), stored.end());
    } catch (const std::bad_alloc&) {
        throw PackageError(ErrorCode::OutOfMemory, file_,
                           "no memory to copy " + detail::sectionName(ours.type, ours.frame));
    }
}

SectionBuffer::SectionBuffer() : zstd_(std::make_unique<detail::ZstdDecompressor>()) {}
SectionBuffer::~SectionBuffer() = default;
SectionBuffer::SectionBuffer(SectionBuffer&&) noexcept = default;
SectionBuffer& SectionBuffer::operator=(SectionBuffer&&) noexcept = default;

std::span<const std::byte> ContainerReader::read(const SectionInfo& section, SectionBuffer& buffer) const {
    const std::size_t index = indexOf(section, "read");
    const SectionInfo& ours = sections_[index];
    const std::span<const std::byte> stored = verifiedStoredBytes(index);
    if (ours.codec != Codec::Zstd) return stored;  // checksum-verified, in place
    if (!buffer.zstd_) buffer.zstd_ = std::make_unique<detail::ZstdDecompressor>();  // a moved-from buffer
    detail::zstdDecompress(stored, ours.raw_size, file_, detail::sectionName(ours.type, ours.frame),
                           buffer.zstd_.get(), buffer.bytes_);
    return {buffer.bytes_.data(), buffer.bytes_.size()};
}

std::span<const std::byte> ContainerReader::stored(const SectionInfo& section) const {
    return verifiedStoredBytes(indexOf(section, "stored"));
}

std::span<const std::byte> ContainerReader::mapped(const SectionInfo& section) const {
    const std::size_t index = indexOf(section, "mapped");
    if (sections_[index].codec != Codec::Raw) {
        throw PackageError(ErrorCode::InvalidArgument, file_,
                           detail::sectionName(section.type, section.frame) +
                               " is zstd-compressed and cannot be viewed in place; use read()");
    }
    return verifiedStoredBytes(index);
}

std::optional<std::string> ContainerReader::metadata() const {
    const SectionInfo* section = find(kMetadataType, kNoFrame);
    if (section == nullptr) return std::nullopt;
    const std::vector<std::byte> bytes = read(*section);
    return std::string(reinterpret_cast<const char*>(bytes.data()), bytes.size());
}

}  // namespace firelook::package
