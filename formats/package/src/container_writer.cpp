#include "package/container_writer.h"

#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <optional>
#include <string>
#include <unordered_set>
#include <utility>
#include <vector>

#include "checksum.h"
#include "common/atomic_file.h"
#include "package/error.h"
#include "section_name.h"
#include "zstd_codec.h"

namespace firelook::package {
namespace {

constexpr std::array<std::byte, kSectionAlignment> kZeros{};

uint64_t alignUp(uint64_t value) {
    return (value + kSectionAlignment - 1) / kSectionAlignment * kSectionAlignment;
}

uint64_t sectionKey(uint32_t type, uint32_t frame) { return (uint64_t{type} << 32) | frame; }

template <typename T>
std::span<const std::byte> bytesOf(const T& value) {
    return std::as_bytes(std::span<const T>(&value, 1));
}

}  // namespace

struct ContainerWriter::Impl {
    enum class State { Open, Failed, Committed };

    Impl(std::filesystem::path destination_path, const WriterOptions& writer_options)
        : destination(std::move(destination_path)),
          options(writer_options),
          compressor(writer_options.zstd_level, destination) {}

    // AtomicFile (common/atomic_file.h) says "<destination>: <problem>"; PackageError adds the file
    // and the code itself. The temporary is already removed.
    [[noreturn]] void fail(const firelook::Error& error, const std::string& during) {
        state = State::Failed;
        std::string problem = error.what();
        const std::string prefix = destination.string() + ": ";
        if (problem.starts_with(prefix)) problem.erase(0, prefix.size());
        throw PackageError(ErrorCode::IoError, destination, problem + (during.empty() ? "" : " (" + during + ")"));
    }

    void writeAll(std::span<const std::byte> bytes, const std::string& what) {
        try {
            file->write(bytes);
        } catch (const firelook::Error& error) {
            fail(error, "writing " + what);
        }
        position += bytes.size();
    }

    void checkNewKey(uint32_t type, uint32_t frame, const std::string& name) const {
        if (keys.contains(sectionKey(type, frame)))
            throw PackageError(ErrorCode::InvalidArgument, destination, name + " was already added");
        if (index.size() >= UINT32_MAX) throw PackageError(ErrorCode::InvalidArgument, destination, "too many sections");
    }

    // Writes one section's stored bytes, padded, and its index entry.
    SectionInfo append(uint32_t type, uint32_t frame, uint32_t flags, Codec codec, std::span<const std::byte> stored,
                       uint64_t raw_size, const std::string& name) {
        IndexEntry entry{};
        entry.type = type;
        entry.frame = frame;
        entry.flags = flags;
        entry.codec = static_cast<uint32_t>(codec);
        entry.offset = position;
        entry.stored_size = stored.size();
        entry.raw_size = raw_size;
        entry.checksum = detail::checksum64(stored);
        writeAll(stored, name);
        padToAlignment();
        index.push_back(entry);
        keys.insert(sectionKey(type, frame));
        return SectionInfo{entry.type, entry.frame, entry.flags, codec, entry.offset, entry.stored_size, entry.raw_size,
                           entry.checksum};
    }

    void padToAlignment() { writeAll(std::span(kZeros).first(alignUp(position) - position), "padding"); }

    std::filesystem::path destination;
    std::filesystem::path temporary;  // kept after commit, for temporaryPath()
    WriterOptions options;
    detail::ZstdCompressor compressor;
    std::optional<AtomicFile> file;  // removes the temporary unless committed
    uint64_t position = 0;  // bytes written to the temporary file so far
    std::vector<IndexEntry> index;
    std::unordered_set<uint64_t> keys;  // (type, frame) pairs already written
    State state = State::Open;
};

ContainerWriter::ContainerWriter(std::filesystem::path destination, WriterOptions options)
    : impl_(std::make_unique<Impl>(std::move(destination), options)) {
    Impl& writer = *impl_;
    try {
        writer.file.emplace(writer.destination);
    } catch (const firelook::Error& error) {
        writer.fail(error, "");
    }
    writer.temporary = writer.file->temporary();
    // The header is written by commit(); until then the file does not claim to be a package.
    writer.writeAll(std::span(kZeros).first(sizeof(FileHeader)), "the header placeholder");
}

ContainerWriter::~ContainerWriter() = default;
ContainerWriter::ContainerWriter(ContainerWriter&&) noexcept = default;
ContainerWriter& ContainerWriter::operator=(ContainerWriter&&) noexcept = default;

ContainerWriter::Impl& ContainerWriter::impl(const char* operation) const {
    if (!impl_) {
        throw PackageError(ErrorCode::InvalidState, {},
                           std::string(operation) + " on a moved-from ContainerWriter");
    }
    if (impl_->state != Impl::State::Open) {
        throw PackageError(
            ErrorCode::InvalidState, impl_->destination,
            std::string(operation) + " after the writer was " +
                (impl_->state == Impl::State::Committed ? "committed" : "stopped by an error"));
    }
    return *impl_;
}

SectionInfo ContainerWriter::addSection(uint32_t type, uint32_t frame, std::span<const std::byte> raw,
                                      Codec codec, bool required) {
    Impl& writer = impl("addSection");
    const std::string name = detail::sectionName(type, frame);
    if (codec != Codec::Raw && codec != Codec::Zstd) {
        throw PackageError(ErrorCode::InvalidArgument, writer.destination,
                           name + ": unknown codec " + std::to_string(static_cast<uint32_t>(codec)));
    }
    writer.checkNewKey(type, frame, name);
    const std::span<const std::byte> stored =
        codec == Codec::Zstd ? writer.compressor.compress(raw, name) : raw;
    return writer.append(type, frame, required ? kSectionRequired : 0u, codec, stored, raw.size(), name);
}

SectionInfo ContainerWriter::addStoredSection(const SectionInfo& section, std::span<const std::byte> stored) {
    Impl& writer = impl("addStoredSection");
    const std::string name = detail::sectionName(section.type, section.frame);
    if (section.codec != Codec::Raw && section.codec != Codec::Zstd) {
        throw PackageError(ErrorCode::InvalidArgument, writer.destination,
                           name + ": unknown codec " + std::to_string(static_cast<uint32_t>(section.codec)));
    }
    if (stored.size() != section.stored_size || detail::checksum64(stored) != section.checksum ||
        (section.codec == Codec::Raw && section.raw_size != section.stored_size)) {
        throw PackageError(ErrorCode::Corrupt, writer.destination,
                           name + ": the stored bytes given do not match their index entry");
    }
    writer.checkNewKey(section.type, section.frame, name);
    return writer.append(section.type, section.frame, section.flags, section.codec, stored, section.raw_size, name);
}

SectionInfo ContainerWriter::addMetadata(std::string_view json) {
    return addSection(kMetadataType, kNoFrame, std::as_bytes(std::span(json.data(), json.size())),
                      Codec::Zstd, true);
}

void ContainerWriter::commit() {
    Impl& writer = impl("commit");
    const std::span<const std::byte> index_bytes = std::as_bytes(std::span(writer.index));

    FileHeader header{};
    std::memcpy(header.identifier, kIdentifier, sizeof kIdentifier);
    header.version_major = kFormatMajor;
    header.version_minor = writer.options.format_minor;
    header.header_size = sizeof(FileHeader);
    header.index_entry_size = sizeof(IndexEntry);
    header.section_count = static_cast<uint32_t>(writer.index.size());
    header.index_offset = writer.position;  // already 64-aligned: every section is padded
    header.file_size = writer.position + index_bytes.size();
    header.index_checksum = detail::checksum64(index_bytes);
    header.header_checksum = detail::checksum64(bytesOf(header).first(offsetof(FileHeader, header_checksum)));

    writer.writeAll(index_bytes, "the index");
    const std::span<const std::byte> header_bytes = bytesOf(header);
    const ssize_t written = ::pwrite(writer.file->fd(), header_bytes.data(), header_bytes.size(), 0);
    if (written != static_cast<ssize_t>(header_bytes.size())) {
        const int error = written >= 0 ? EIO : errno;  // a short write of 64 bytes leaves no errno of its own
        writer.file->discard();
        writer.state = Impl::State::Failed;
        throw PackageError(ErrorCode::IoError, writer.destination,
                           "cannot write the header (temporary file " + writer.temporary.string() +
                               "): " + std::strerror(error));
    }
    try {
        writer.file->commit();  // fsync, rename onto the destination, fsync of the folder
    } catch (const firelook::Error& error) {
        writer.fail(error, "");
    }
    writer.state = Impl::State::Committed;
}

const std::filesystem::path& ContainerWriter::destination() const {
    if (!impl_)
        throw PackageError(ErrorCode::InvalidState, {}, "destination() on a moved-from ContainerWriter");
    return impl_->destination;
}

const std::filesystem::path& ContainerWriter::temporaryPath() const {
    if (!impl_)
        throw PackageError(ErrorCode::InvalidState, {}, "temporaryPath() on a moved-from ContainerWriter");
    return impl_->temporary;
}

struct StoredSizeMeter::Impl {
    detail::ZstdCompressor compressor;
};

StoredSizeMeter::StoredSizeMeter(WriterOptions options)
    : impl_(std::make_unique<Impl>(Impl{detail::ZstdCompressor(options.zstd_level, "(size estimate)")})) {}
StoredSizeMeter::~StoredSizeMeter() = default;
StoredSizeMeter::StoredSizeMeter(StoredSizeMeter&&) noexcept = default;
StoredSizeMeter& StoredSizeMeter::operator=(StoredSizeMeter&&) noexcept = default;

uint64_t StoredSizeMeter::storedBytes(std::span<const std::byte> raw) {
    return impl_->compressor.compress(raw, "a section").size();
}

}  // namespace firelook::package
