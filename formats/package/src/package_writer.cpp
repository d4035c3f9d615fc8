#include "package/package_writer.h"

#include <fcntl.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <string>
#include <unordered_set>
#include <utility>
#include <vector>

#include "checksum.h"
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

// Opens a fresh file beside `destination`, created with mode 0666 so the umask applies as for any
// other new file (mkstemp would force 0600 on the published package).
int createTemporary(const std::filesystem::path& destination, std::filesystem::path& temporary) {
    static std::atomic<unsigned> counter{0};
    const std::filesystem::path folder = destination.has_parent_path() ? destination.parent_path() : ".";
    for (int attempt = 0; attempt < 100; ++attempt) {
        temporary = folder / ("." + destination.filename().string() + "." + std::to_string(::getpid()) + "-" +
                              std::to_string(counter.fetch_add(1)) + ".tmp");
        const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0 || errno != EEXIST) return fd;
    }
    errno = EEXIST;
    return -1;
}

}  // namespace

struct PackageWriter::Impl {
    enum class State { Open, Failed, Committed };

    Impl(std::filesystem::path destination_path, const WriterOptions& writer_options)
        : destination(std::move(destination_path)),
          options(writer_options),
          compressor(writer_options.zstd_level, destination) {}

    ~Impl() {
        if (fd >= 0) ::close(fd);
        if (state != State::Committed && !temporary.empty()) ::unlink(temporary.c_str());
    }

    [[noreturn]] void fail(const std::string& action) {
        const int error = errno;
        state = State::Failed;
        throw PackageError(
            ErrorCode::IoError, destination,
            "cannot " + action + " (temporary file " + temporary.string() + "): " + std::strerror(error));
    }

    void writeAll(std::span<const std::byte> bytes, const std::string& what) {
        while (!bytes.empty()) {
            const ssize_t written = ::write(fd, bytes.data(), bytes.size());
            if (written < 0 && errno == EINTR) continue;
            if (written < 0) fail("write " + what);
            bytes = bytes.subspan(static_cast<std::size_t>(written));
            position += static_cast<uint64_t>(written);
        }
    }

    void padToAlignment() { writeAll(std::span(kZeros).first(alignUp(position) - position), "padding"); }

    std::filesystem::path destination;
    std::filesystem::path temporary;
    WriterOptions options;
    detail::ZstdCompressor compressor;
    int fd = -1;
    uint64_t position = 0;  // bytes written to the temporary file so far
    std::vector<IndexEntry> index;
    std::unordered_set<uint64_t> keys;  // (type, frame) pairs already written
    State state = State::Open;
};

PackageWriter::PackageWriter(std::filesystem::path destination, WriterOptions options)
    : impl_(std::make_unique<Impl>(std::move(destination), options)) {
    Impl& writer = *impl_;
    writer.fd = createTemporary(writer.destination, writer.temporary);
    if (writer.fd < 0) {
        const int error = errno;
        writer.temporary.clear();
        throw PackageError(ErrorCode::IoError, writer.destination,
                           std::string("cannot create a temporary file beside it: ") + std::strerror(error));
    }
    // The header is written by commit(); until then the file does not claim to be a package.
    writer.writeAll(std::span(kZeros).first(sizeof(FileHeader)), "the header placeholder");
}

PackageWriter::~PackageWriter() = default;
PackageWriter::PackageWriter(PackageWriter&&) noexcept = default;
PackageWriter& PackageWriter::operator=(PackageWriter&&) noexcept = default;

PackageWriter::Impl& PackageWriter::impl(const char* operation) const {
    if (!impl_) {
        throw PackageError(ErrorCode::InvalidState, {},
                           std::string(operation) + " on a moved-from PackageWriter");
    }
    if (impl_->state != Impl::State::Open) {
        throw PackageError(
            ErrorCode::InvalidState, impl_->destination,
            std::string(operation) + " after the writer was " +
                (impl_->state == Impl::State::Committed ? "committed" : "stopped by an error"));
    }
    return *impl_;
}

SectionInfo PackageWriter::addSection(uint32_t type, uint32_t frame, std::span<const std::byte> raw,
                                      Codec codec, bool required) {
    Impl& writer = impl("addSection");
    const std::string name = detail::sectionName(type, frame);
    if (codec != Codec::Raw && codec != Codec::Zstd) {
        throw PackageError(ErrorCode::InvalidArgument, writer.destination,
                           name + ": unknown codec " + std::to_string(static_cast<uint32_t>(codec)));
    }
    if (writer.keys.contains(sectionKey(type, frame))) {
        throw PackageError(ErrorCode::InvalidArgument, writer.destination, name + " was already added");
    }
    if (writer.index.size() >= UINT32_MAX) {
        throw PackageError(ErrorCode::InvalidArgument, writer.destination, "too many sections");
    }
    const std::span<const std::byte> stored =
        codec == Codec::Zstd ? writer.compressor.compress(raw, name) : raw;

    IndexEntry entry{};
    entry.type = type;
    entry.frame = frame;
    entry.flags = required ? kSectionRequired : 0u;
    entry.codec = static_cast<uint32_t>(codec);
    entry.offset = writer.position;
    entry.stored_size = stored.size();
    entry.raw_size = raw.size();
    entry.checksum = detail::checksum64(stored);
    writer.writeAll(stored, name);
    writer.padToAlignment();
    writer.index.push_back(entry);
    writer.keys.insert(sectionKey(type, frame));

    return SectionInfo{entry.type,   entry.frame,       entry.flags,    codec,
                       entry.offset, entry.stored_size, entry.raw_size, entry.checksum};
}

SectionInfo PackageWriter::addMetadata(std::string_view json) {
    return addSection(kMetadataType, kNoFrame, std::as_bytes(std::span(json.data(), json.size())),
                      Codec::Zstd, true);
}

void PackageWriter::commit() {
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
    const ssize_t written = ::pwrite(writer.fd, header_bytes.data(), header_bytes.size(), 0);
    if (written != static_cast<ssize_t>(header_bytes.size())) {
        if (written >= 0) errno = EIO;  // a short write of 64 bytes leaves no errno of its own
        writer.fail("write the header");
    }
    if (::fsync(writer.fd) != 0) writer.fail("flush to disk");
    const int fd = std::exchange(writer.fd, -1);
    if (::close(fd) != 0) writer.fail("close");
    if (::rename(writer.temporary.c_str(), writer.destination.c_str()) != 0)
        writer.fail("rename onto the destination");
    writer.state = Impl::State::Committed;

    // Make the rename itself durable. Best effort: the package is already published, and some file
    // systems refuse fsync on a folder.
    const std::filesystem::path folder =
        writer.destination.has_parent_path() ? writer.destination.parent_path() : ".";
    const int folder_fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (folder_fd >= 0) {
        ::fsync(folder_fd);
        ::close(folder_fd);
    }
}

const std::filesystem::path& PackageWriter::destination() const {
    if (!impl_)
        throw PackageError(ErrorCode::InvalidState, {}, "destination() on a moved-from PackageWriter");
    return impl_->destination;
}

const std::filesystem::path& PackageWriter::temporaryPath() const {
    if (!impl_)
        throw PackageError(ErrorCode::InvalidState, {}, "temporaryPath() on a moved-from PackageWriter");
    return impl_->temporary;
}

}  // namespace firelook::package
