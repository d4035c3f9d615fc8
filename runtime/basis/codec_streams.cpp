// The frame codec's byte level (codec_streams.h).
#include "basis/codec_streams.h"

#include <algorithm>

namespace firelook::basis::codec {
namespace {

// The median edge detector of LOCO-I / JPEG-LS: from the left (a), upper (b) and upper-left (c)
// neighbours. Its result lies between a and b, so a prediction of int16 values is an int16.
inline int medPredict(int a, int b, int c) {
    const int lo = std::min(a, b), hi = std::max(a, b);
    if (c >= hi) return lo;
    if (c <= lo) return hi;
    return a + b - c;
}

inline int predictAt(const int16_t* v, int x, int y, int w) {
    const size_t i = static_cast<size_t>(y) * w + x;
    if (y == 0) return x == 0 ? 0 : v[i - 1];
    if (x == 0) return v[i - w];
    return medPredict(v[i - 1], v[i - w], v[i - w - 1]);
}

// Residuals modulo 2^16, zig-zagged (small magnitudes -> small codes), so the inverse recovers
// every int16 exactly whatever the residual's size.
inline uint16_t zigzag(int16_t r) { return static_cast<uint16_t>((static_cast<uint16_t>(r) << 1) ^ static_cast<uint16_t>(r >> 15)); }
inline int16_t unzigzag(uint16_t z) { return static_cast<int16_t>((z >> 1) ^ (0u - (z & 1u))); }

}  // namespace

void predictPlane(const int16_t* values, int w, int h, const uint8_t* mask, std::vector<uint16_t>& codes) {
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t i = static_cast<size_t>(y) * w + x;
            if (mask && !mask[i]) continue;
            codes.push_back(zigzag(static_cast<int16_t>(values[i] - predictAt(values, x, y, w))));
        }
}

void putShuffled(ByteWriter& out, const std::vector<uint16_t>& codes) {
    std::byte* p = out.grow(codes.size() * 2);
    for (size_t i = 0; i < codes.size(); ++i) {
        p[i] = static_cast<std::byte>(codes[i] & 0xFF);
        p[codes.size() + i] = static_cast<std::byte>(codes[i] >> 8);
    }
}

void putRuns(ByteWriter& out, const std::vector<uint8_t>& occupied) {
    std::vector<uint32_t> runs;
    size_t end = 0;
    for (size_t i = 0; i < occupied.size();) {
        if (!occupied[i]) {
            ++i;
            continue;
        }
        size_t j = i;
        while (j < occupied.size() && occupied[j]) ++j;
        runs.push_back(static_cast<uint32_t>(i - end));
        runs.push_back(static_cast<uint32_t>(j - i));
        end = i = j;
    }
    out.put<uint32_t>(static_cast<uint32_t>(runs.size() / 2));
    for (uint32_t v : runs) out.put<uint32_t>(v);
}

std::vector<uint8_t> occupiedItems(const int16_t* planes, size_t count, size_t items) {
    std::vector<uint8_t> occupied(items, 0);
    for (size_t i = 0; i < count; ++i)
        for (size_t j = 0; j < items; ++j) occupied[j] |= planes[i * items + j] != 0;
    return occupied;
}

std::vector<uint16_t> transpose(const uint16_t* codes, size_t planes, size_t items) {
    std::vector<uint16_t> out(planes * items);
    for (size_t i = 0; i < planes; ++i)
        for (size_t j = 0; j < items; ++j) out[j * planes + i] = codes[i * items + j];
    return out;
}

std::vector<uint16_t> getShuffled(ByteReader& in, size_t count) {
    const std::byte* p = in.need(count * 2);
    std::vector<uint16_t> codes(count);
    for (size_t i = 0; i < count; ++i)
        codes[i] = static_cast<uint16_t>(static_cast<unsigned>(p[i]) | static_cast<unsigned>(p[count + i]) << 8);
    return codes;
}

}  // namespace firelook::basis::codec
