#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

struct ZSTD_CCtx_s;
struct ZSTD_DCtx_s;

namespace firelook::package::detail {

// The largest raw size a zstd frame of `stored_size` bytes can decode to: every block holds at most
// 128 KiB and takes at least 4 bytes (3-byte header + 1 byte of RLE payload). Lets a reader reject
// an absurd raw size before it allocates.
uint64_t maxZstdRawSize(uint64_t stored_size);

// Compresses one section at a time into a buffer it reuses, so a writer holds at most one
// compressed section in memory. Single-threaded zstd: the same input gives the same bytes.
class ZstdCompressor {
  public:
    // Throws PackageError(InvalidArgument) naming `file` when `level` is outside zstd's range.
    ZstdCompressor(int level, std::filesystem::path file);
    ~ZstdCompressor();
    ZstdCompressor(ZstdCompressor&&) noexcept = default;
    ZstdCompressor& operator=(ZstdCompressor&&) noexcept = default;

    // One zstd frame recording the raw size; valid until the next call.
    std::span<const std::byte> compress(std::span<const std::byte> raw, const std::string& what);

  private:
    struct ContextDeleter {
        void operator()(ZSTD_CCtx_s* context) const;
    };
    std::unique_ptr<ZSTD_CCtx_s, ContextDeleter> context_;
    std::vector<std::byte> buffer_;
    std::filesystem::path file_;
};

// Decodes `stored`, which must be exactly one zstd frame recording a content size of `raw_size`.
// Throws PackageError naming `file` and `what` (Corrupt, UnsupportedFeature or OutOfMemory).
std::vector<std::byte> zstdDecompress(std::span<const std::byte> stored, uint64_t raw_size,
                                      const std::filesystem::path& file, const std::string& what);

// A zstd decompression context kept between calls (created on first use).
struct ZstdDecompressor {
    struct ContextDeleter {
        void operator()(ZSTD_DCtx_s* context) const;
    };
    std::unique_ptr<ZSTD_DCtx_s, ContextDeleter> context;
};

// The same into `raw` (its capacity reused), with `decompressor`'s context when not null.
void zstdDecompress(std::span<const std::byte> stored, uint64_t raw_size, const std::filesystem::path& file,
                    const std::string& what, ZstdDecompressor* decompressor, std::vector<std::byte>& raw);

}  // namespace firelook::package::detail
