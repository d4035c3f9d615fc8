#include "zstd_codec.h"

#include <zstd.h>
#include <zstd_errors.h>

#include <new>

#include "package/error.h"

namespace firelook::package::detail {
namespace {

ErrorCode compressionErrorCode(size_t result) {
    switch (ZSTD_getErrorCode(result)) {
        case ZSTD_error_memory_allocation:
            return ErrorCode::OutOfMemory;
        case ZSTD_error_parameter_unsupported:
        case ZSTD_error_parameter_combination_unsupported:
        case ZSTD_error_parameter_outOfBound:
            return ErrorCode::InvalidArgument;
        default:
            return ErrorCode::CompressionFailed;
    }
}

ErrorCode decompressionErrorCode(size_t result) {
    switch (ZSTD_getErrorCode(result)) {
        case ZSTD_error_memory_allocation:
            return ErrorCode::OutOfMemory;
        // A well-formed frame that needs something this build does not do.
        case ZSTD_error_frameParameter_unsupported:
        case ZSTD_error_frameParameter_windowTooLarge:
        case ZSTD_error_version_unsupported:
        case ZSTD_error_dictionary_wrong:
            return ErrorCode::UnsupportedFeature;
        default:
            return ErrorCode::Corrupt;
    }
}

}  // namespace

uint64_t maxZstdRawSize(uint64_t stored_size) {
    constexpr uint64_t kMaxBlockContent = 128 * 1024;
    constexpr uint64_t kMinBlockBytes = 4;
    return (stored_size / kMinBlockBytes + 1) * kMaxBlockContent;
}

void ZstdCompressor::ContextDeleter::operator()(ZSTD_CCtx_s* context) const { ZSTD_freeCCtx(context); }

ZstdCompressor::ZstdCompressor(int level, std::filesystem::path file) : file_(std::move(file)) {
    if (level < ZSTD_minCLevel() || level > ZSTD_maxCLevel()) {
        throw PackageError(ErrorCode::InvalidArgument, file_,
                           "zstd level " + std::to_string(level) + " is outside [" +
                               std::to_string(ZSTD_minCLevel()) + ", " + std::to_string(ZSTD_maxCLevel()) +
                               "]");
    }
    context_.reset(ZSTD_createCCtx());
    if (!context_)
        throw PackageError(ErrorCode::OutOfMemory, file_, "cannot create a zstd compression context");
    for (const auto& [parameter, value] : {std::pair{ZSTD_c_compressionLevel, level},
                                           std::pair{ZSTD_c_contentSizeFlag, 1},  // the reader checks it
                                           std::pair{ZSTD_c_checksumFlag, 0}}) {  // the index has XXH3
        const size_t result = ZSTD_CCtx_setParameter(context_.get(), parameter, value);
        if (ZSTD_isError(result)) {
            throw PackageError(compressionErrorCode(result), file_,
                               std::string("zstd rejected a parameter: ") + ZSTD_getErrorName(result));
        }
    }
}

ZstdCompressor::~ZstdCompressor() = default;

std::span<const std::byte> ZstdCompressor::compress(std::span<const std::byte> raw, const std::string& what) {
    try {
        buffer_.resize(ZSTD_compressBound(raw.size()));
    } catch (const std::bad_alloc&) {
        throw PackageError(ErrorCode::OutOfMemory, file_, "no memory to compress " + what);
    }
    const size_t result =
        ZSTD_compress2(context_.get(), buffer_.data(), buffer_.size(), raw.data(), raw.size());
    if (ZSTD_isError(result)) {
        throw PackageError(compressionErrorCode(result), file_,
                           "zstd failed on " + what + ": " + ZSTD_getErrorName(result));
    }
    return std::span<const std::byte>(buffer_.data(), result);
}

void ZstdDecompressor::ContextDeleter::operator()(ZSTD_DCtx_s* context) const { ZSTD_freeDCtx(context); }

std::vector<std::byte> zstdDecompress(std::span<const std::byte> stored, uint64_t raw_size,
                                      const std::filesystem::path& file, const std::string& what) {
    std::vector<std::byte> raw;
    zstdDecompress(stored, raw_size, file, what, nullptr, raw);
    return raw;
}

void zstdDecompress(std::span<const std::byte> stored, uint64_t raw_size, const std::filesystem::path& file,
                    const std::string& what, ZstdDecompressor* decompressor, std::vector<std::byte>& raw) {
    const size_t frame_size = ZSTD_findFrameCompressedSize(stored.data(), stored.size());
    if (ZSTD_isError(frame_size)) {
        throw PackageError(decompressionErrorCode(frame_size), file,
                           what + " is not a valid zstd frame: " + ZSTD_getErrorName(frame_size));
    }
    if (frame_size != stored.size()) {
        throw PackageError(ErrorCode::Corrupt, file,
                           what + " holds " + std::to_string(stored.size()) +
                               " stored bytes but its zstd frame ends after " + std::to_string(frame_size));
    }
    const unsigned long long content_size = ZSTD_getFrameContentSize(stored.data(), stored.size());
    if (content_size == ZSTD_CONTENTSIZE_UNKNOWN || content_size == ZSTD_CONTENTSIZE_ERROR) {
        throw PackageError(ErrorCode::Corrupt, file,
                           what + ": the zstd frame does not record its content size");
    }
    if (content_size != raw_size) {
        throw PackageError(ErrorCode::Corrupt, file,
                           what + ": the zstd frame decodes to " + std::to_string(content_size) +
                               " bytes but the index says " + std::to_string(raw_size));
    }
    try {
        raw.resize(raw_size);
    } catch (const std::bad_alloc&) {
        throw PackageError(ErrorCode::OutOfMemory, file,
                           "no memory for the " + std::to_string(raw_size) + " decoded bytes of " + what);
    }
    ZSTD_DCtx* context = nullptr;
    if (decompressor) {
        if (!decompressor->context) decompressor->context.reset(ZSTD_createDCtx());
        context = decompressor->context.get();
    }
    const size_t result = context ? ZSTD_decompressDCtx(context, raw.data(), raw.size(), stored.data(), stored.size())
                                  : ZSTD_decompress(raw.data(), raw.size(), stored.data(), stored.size());
    if (ZSTD_isError(result)) {
        throw PackageError(decompressionErrorCode(result), file,
                           "zstd failed to decode " + what + ": " + ZSTD_getErrorName(result));
    }
    if (result != raw_size) {
        throw PackageError(
            ErrorCode::Corrupt, file,
            what + " decoded to " + std::to_string(result) + " bytes, expected " + std::to_string(raw_size));
    }
}

}  // namespace firelook::package::detail
