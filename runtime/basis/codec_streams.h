// The frame codec's byte level (internal to runtime/basis; docs/package-format.md, "Frame codec"),
// shared by its encoder (frame_encoder.cpp) and decoder (frame_decoder.cpp): the payload version,
// little-endian byte streams with bounds checks, the prediction of int16 planes, runs of occupied
// items and the two-byte-plane layout of the codes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/error.h"

namespace firelook::basis::codec {

// Payload version: 3 leaves out the items that are all zero (most pixels lie outside the fire's
// footprint), so neither zstd nor the decoder spends time on them; 2 stored every item's codes
// together (a pixel's rank values, a ray's depth planes), so the decoder undoes the prediction of
// all planes at once; 1 stored plane after plane. 4 stores one S V^T step per column of a grid
// point (each light source on its own grid, basis/source_balance.h); its UFAC and ODEP payloads
// are version 3's. All four are read.
inline constexpr uint32_t kCodecVersion = 4;
// What SVTF's first f64 holds from version 4 on, where versions 1-3 held the one step (a step of
// 0 is refused by them, so an older reader names the payload instead of misreading it).
inline constexpr double kPerColumnSteps = 0.0;

// ---- little-endian byte streams with bounds checks ------------------------------------------
class ByteWriter {
  public:
    template <typename T>
    void put(T value) {
        const size_t at = bytes_.size();
        bytes_.resize(at + sizeof(T));
        std::memcpy(bytes_.data() + at, &value, sizeof(T));
    }
    std::byte* grow(size_t count) {
        const size_t at = bytes_.size();
        bytes_.resize(at + count);
        return bytes_.data() + at;
    }
    std::vector<std::byte> take() { return std::move(bytes_); }

  private:
    std::vector<std::byte> bytes_;
};

class ByteReader {
  public:
    ByteReader(std::span<const std::byte> bytes, std::string what) : bytes_(bytes), what_(std::move(what)) {}
    template <typename T>
    T get() {
        T value;
        std::memcpy(&value, need(sizeof(T)), sizeof(T));
        return value;
    }
    const std::byte* need(size_t count) {
        if (count > bytes_.size() - at_) fail("ends early");
        const std::byte* p = bytes_.data() + at_;
        at_ += count;
        return p;
    }
    void expectEnd() const {
        if (at_ != bytes_.size()) fail("has " + std::to_string(bytes_.size() - at_) + " bytes too many");
    }
    [[noreturn]] void fail(const std::string& problem) const {
        throw Error(ErrorCode::Corrupt, what_ + " " + problem);
    }

  private:
    std::span<const std::byte> bytes_;
    size_t at_ = 0;
    std::string what_;
};

// Residuals of a plane, appended to `codes` in scan order; with a mask, only where it is 1 (the
// other values are known to the decoder already and still serve as neighbours).
void predictPlane(const int16_t* values, int w, int h, const uint8_t* mask, std::vector<uint16_t>& codes);

// Codes as two byte planes (all low bytes, then all high bytes): most high bytes are 0, which
// zstd then stores as one long run.
void putShuffled(ByteWriter& out, const std::vector<uint16_t>& codes);
// The inverse of putShuffled for `count` codes.
std::vector<uint16_t> getShuffled(ByteReader& in, size_t count);

// Occupied items (scan order) as runs: u32 count, then per run u32 gap (items since the end of
// the previous run) and u32 length. A blob-shaped footprint takes a few runs per row.
void putRuns(ByteWriter& out, const std::vector<uint8_t>& occupied);

// Items whose planes (plane-major, `items` values each) are all 0.
std::vector<uint8_t> occupiedItems(const int16_t* planes, size_t count, size_t items);

// Plane-major codes (plane after plane, `items` codes each) to item-major (an item's `planes`
// codes together), the order version 2 stores; `transpose(codes, items, planes)` is the inverse.
std::vector<uint16_t> transpose(const uint16_t* codes, size_t planes, size_t items);

}  // namespace firelook::basis::codec
