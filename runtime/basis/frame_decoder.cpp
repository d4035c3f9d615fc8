// The frame codec's decoder (frame_codec.h): payloads of versions 1 to 4 into the resident form,
#include "basis/frame_codec.h"

// the prediction undone by SIMD kernels (basis/simd.h) with an item's planes in the lanes.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>

#include "basis/codec_streams.h"
#include "basis/depth_companding.h"
#include "basis/ray_lattice.h"
#include "basis/simd.h"

namespace firelook::basis {
namespace {

using codec::ByteReader;
using codec::getShuffled;
using codec::kCodecVersion;
using codec::kPerColumnSteps;
using codec::RayLattice;
using codec::transpose;
using simd::v8b;
using simd::v8s;
using simd::v8u;

// Item-major codes (version 2's order) as their two byte planes: code i = lo[i] | hi[i] << 8.
struct CodeStream {
    const uint8_t* lo = nullptr;
    const uint8_t* hi = nullptr;
    size_t count = 0;

    static CodeStream of(ByteReader& in, size_t count) {
        const auto* p = reinterpret_cast<const uint8_t*>(in.need(count * 2));
        return {p, p + count, count};
    }
    // Codes [at, at + n), n <= lanes of S (8 or 16), zig-zag undone; lanes from n on are 0.
    // Reads whole vectors wherever the stream has them and masks the rest (a short copy only at
    // the stream's very end).
    template <typename S, typename U, typename B>
    FIRELOOK_ALWAYS_INLINE void residuals(S& out, size_t at, int n) const {
        constexpr int kLanes = sizeof(S) / 2;
        B l = {}, h = {};
        if (at + kLanes <= count) {
            simd::load(l, lo + at);
            simd::load(h, hi + at);
            if (n < kLanes) {
                B lane;
                if constexpr (kLanes == 8)
                    lane = B{0, 1, 2, 3, 4, 5, 6, 7};
                else
                    lane = B{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
                const B keep = reinterpret_cast<B>(lane < static_cast<uint8_t>(n));
                l &= keep;
                h &= keep;
            }
        } else {
            for (int i = 0; i < n; ++i) {
                l[i] = lo[at + i];
                h[i] = hi[at + i];
            }
        }
        const U z = __builtin_convertvector(l, U) | (__builtin_convertvector(h, U) << 8);
        out = reinterpret_cast<S>((z >> 1) ^ (U{} - (z & 1)));
    }
};

// A version-1 payload's plane-major codes rewritten in version 2's order (segments of `planes`
// planes of `items` codes each, one after another), so one decoder serves both.
struct ReorderedCodes {
    std::vector<uint8_t> bytes;
    CodeStream stream;
    ReorderedCodes(ByteReader& in, std::initializer_list<std::pair<size_t, size_t>> segments) {
        size_t count = 0;
        for (const auto& [planes, items] : segments) count += planes * items;
        const std::vector<uint16_t> plane_major = getShuffled(in, count);
        bytes.resize(count * 2);
        size_t at = 0;
        for (const auto& [planes, items] : segments) {
            const std::vector<uint16_t> codes = transpose(plane_major.data() + at, planes, items);
            for (size_t i = 0; i < codes.size(); ++i) {
                bytes[at + i] = static_cast<uint8_t>(codes[i] & 0xFF);
                bytes[count + at + i] = static_cast<uint8_t>(codes[i] >> 8);
            }
            at += planes * items;
        }
        stream = {bytes.data(), bytes.data() + count, count};
    }
};

// The median edge detector (medPredict, codec_streams.cpp) on 8 or 16 planes at once; the sums wrap as int16
// arithmetic does in the scalar encoder.
template <typename S, typename U>
FIRELOOK_ALWAYS_INLINE void medPredictLanes(S& out, const S& a, const S& b, const S& c) {
    const S lo = a < b ? a : b, hi = a < b ? b : a;
    const S mid = reinterpret_cast<S>(reinterpret_cast<U>(a) + reinterpret_cast<U>(b) - reinterpret_cast<U>(c));
    out = c >= hi ? lo : (c <= lo ? hi : mid);
}

// Lanes [g, g + width of S) of one item from its prediction (neighbours may be null: the
// predictAt edge rules).
template <typename S, typename U, typename B>
FIRELOOK_ALWAYS_INLINE void decodeLanes(const CodeStream& codes, size_t first_code, int lanes, int g,
                                        const int16_t* left, const int16_t* up, const int16_t* up_left,
                                        int16_t* out) {
    S r, prediction = {};
    codes.residuals<S, U, B>(r, first_code + g, std::min<int>(sizeof(S) / 2, lanes - g));
    if (left && up) {
        S a, b, c;
        simd::load(a, left + g);
        simd::load(b, up + g);
        simd::load(c, up_left + g);
        medPredictLanes<S, U>(prediction, a, b, c);
    } else if (left) {
        simd::load(prediction, left + g);
    } else if (up) {
        simd::load(prediction, up + g);
    }
    const S v = reinterpret_cast<S>(reinterpret_cast<U>(prediction) + reinterpret_cast<U>(r));
    simd::store(out + g, v);
}

// One item (stride a multiple of 8): 16 lanes at a time, then 8.
FIRELOOK_ALWAYS_INLINE void decodeItem(const CodeStream& codes, size_t first_code, int lanes, int stride,
                                       const int16_t* left, const int16_t* up, const int16_t* up_left,
                                       int16_t* out) {
    int g = 0;
    for (; g + 16 <= stride; g += 16)
        decodeLanes<simd::v16s, simd::v16u, simd::v16b>(codes, first_code, lanes, g, left, up, up_left, out);
    if (g < stride) decodeLanes<v8s, v8u, v8b>(codes, first_code, lanes, g, left, up, up_left, out);
}

// Items [first, first + count) of an image in scan order: the ones a payload codes.
struct Run {
    size_t first = 0, count = 0;
};

// Version 3's runs (putRuns) of the occupied items among `items`.
std::vector<Run> getRuns(ByteReader& in, size_t items) {
    const uint32_t n = in.get<uint32_t>();
    const std::byte* p = in.need(static_cast<size_t>(n) * 8);  // refuses a count the payload cannot hold
    std::vector<Run> runs(n);
    size_t end = 0;
    for (Run& run : runs) {
        uint32_t gap, count;
        std::memcpy(&gap, p, 4);
        std::memcpy(&count, p + 4, 4);
        p += 8;
        if (count == 0 || gap > items - end || count > items - end - gap) in.fail("has an invalid run of occupied items");
        run = {end + gap, count};
        end = run.first + run.count;
    }
    return runs;
}

// Every item, for the versions that code them all.
std::vector<Run> allItems(size_t items) { return items > 0 ? std::vector<Run>{{0, items}} : std::vector<Run>{}; }

size_t itemsIn(const std::vector<Run>& runs) {
    size_t n = 0;
    for (const Run& run : runs) n += run.count;
    return n;
}

// Residuals from their two code bytes (zig-zag undone).
template <typename S, typename U, typename B>
FIRELOOK_ALWAYS_INLINE void unzigzagLanes(S& out, const B& lo, const B& hi) {
    const U z = __builtin_convertvector(lo, U) | (__builtin_convertvector(hi, U) << 8);
    out = reinterpret_cast<S>((z >> 1) ^ (U{} - (z & 1)));
}

// Items [x0, x1) of one row (`row` points at its item 0; `up_row` at the row above's, null on the
// first row), `N8` x 8 lanes apart, from codes[code ...]: the row's left and upper-left
// neighbours are carried in registers from item to item, so each item reads only its codes and
// its upper neighbour, and the chain from one item to the next is the prediction and one add.
// Outside the image the neighbours are 0, which gives predictAt's edge rules (the median of a, 0
// and 0 is a). Returns the next code.
template <int N8>
FIRELOOK_ALWAYS_INLINE size_t decodeRowSegment(const CodeStream& codes, size_t code, int lanes, const int16_t* up_row,
                                               int16_t* row, size_t x0, size_t x1) {
    using simd::v16b;
    using simd::v16s;
    using simd::v16u;
    constexpr int kWide = N8 / 2;           // 16-lane groups
    constexpr bool kTail = N8 % 2 != 0;     // then one of 8 lanes
    constexpr size_t kStride = 8 * N8;
    constexpr int kWideSlots = kWide > 0 ? kWide : 1;
    v16s left[kWideSlots] = {}, up_left[kWideSlots] = {};
    v8s left8 = {}, up_left8 = {};
    if (x0 > 0) {
        const int16_t* l = row + (x0 - 1) * kStride;
#pragma GCC unroll 8
        for (int g = 0; g < kWide; ++g) simd::load(left[g], l + 16 * g);
        if constexpr (kTail) simd::load(left8, l + 16 * kWide);
        if (up_row) {
            const int16_t* ul = up_row + (x0 - 1) * kStride;
#pragma GCC unroll 8
            for (int g = 0; g < kWide; ++g) simd::load(up_left[g], ul + 16 * g);
            if constexpr (kTail) simd::load(up_left8, ul + 16 * kWide);
        }
    }
    // Lanes at or beyond `lanes` hold the next item's codes in the stream: masked to 0.
    v16b keep[kWideSlots] = {};
    v8b keep8 = {};
    for (int g = 0; g < kWide; ++g)
        for (int l = 0; l < 16; ++l) keep[g][l] = 16 * g + l < lanes ? 0xFF : 0;
    for (int l = 0; l < 8; ++l) keep8[l] = 16 * kWide + l < lanes ? 0xFF : 0;
    for (size_t x = x0; x < x1; ++x, code += static_cast<size_t>(lanes)) {
        int16_t* item = row + x * kStride;
        const int16_t* up = up_row ? up_row + x * kStride : nullptr;
        // Whole vectors of codes where the stream has them (the last items: a careful read).
        const bool whole = code + kStride <= codes.count;
#pragma GCC unroll 8
        for (int g = 0; g < kWide; ++g) {
            v16s r;
            if (whole) {
                v16b lo, hi;
                simd::load(lo, codes.lo + code + 16 * g);
                simd::load(hi, codes.hi + code + 16 * g);
                unzigzagLanes<v16s, v16u, v16b>(r, lo & keep[g], hi & keep[g]);
            } else {
                codes.residuals<v16s, v16u, v16b>(r, code + 16 * g, std::clamp(lanes - 16 * g, 0, 16));
            }
            v16s b = {};
            if (up) simd::load(b, up + 16 * g);
            v16s prediction;
            medPredictLanes<v16s, v16u>(prediction, left[g], b, up_left[g]);
            const v16s v = reinterpret_cast<v16s>(reinterpret_cast<v16u>(prediction) + reinterpret_cast<v16u>(r));
            simd::store(item + 16 * g, v);
            left[g] = v;
            up_left[g] = b;
        }
        if constexpr (kTail) {
            v8s r;
            if (whole) {
                v8b lo, hi;
                simd::load(lo, codes.lo + code + 16 * kWide);
                simd::load(hi, codes.hi + code + 16 * kWide);
                unzigzagLanes<v8s, v8u, v8b>(r, lo & keep8, hi & keep8);
            } else {
                codes.residuals<v8s, v8u, v8b>(r, code + 16 * kWide, std::clamp(lanes - 16 * kWide, 0, 8));
            }
            v8s b = {};
            if (up) simd::load(b, up + 16 * kWide);
            v8s prediction;
            medPredictLanes<v8s, v8u>(prediction, left8, b, up_left8);
            const v8s v = reinterpret_cast<v8s>(reinterpret_cast<v8u>(prediction) + reinterpret_cast<v8u>(r));
            simd::store(item + 16 * kWide, v);
            left8 = v;
            up_left8 = b;
        }
    }
    return code;
}

// One row's items [x0, x1) (`r` points at the row's item 0, the row above `row` values before it
// when `has_up`): strides up to 64 lanes with neighbours in registers, wider ones item by item.
// Returns the next code. (A function, not a lambda: a lambda would not be built for the caller's
// target clone.)
FIRELOOK_ALWAYS_INLINE size_t decodeSegment(const CodeStream& codes, size_t code, int lanes, int stride, size_t row,
                                            int16_t* r, bool has_up, size_t x0, size_t x1) {
    const int16_t* up = has_up ? r - row : nullptr;
    switch (stride / 8) {
        case 1: return decodeRowSegment<1>(codes, code, lanes, up, r, x0, x1);
        case 2: return decodeRowSegment<2>(codes, code, lanes, up, r, x0, x1);
        case 3: return decodeRowSegment<3>(codes, code, lanes, up, r, x0, x1);
        case 4: return decodeRowSegment<4>(codes, code, lanes, up, r, x0, x1);
        case 5: return decodeRowSegment<5>(codes, code, lanes, up, r, x0, x1);
        case 6: return decodeRowSegment<6>(codes, code, lanes, up, r, x0, x1);
        case 7: return decodeRowSegment<7>(codes, code, lanes, up, r, x0, x1);
        case 8: return decodeRowSegment<8>(codes, code, lanes, up, r, x0, x1);
        default: break;
    }
    for (size_t x = x0; x < x1; ++x, code += static_cast<size_t>(lanes)) {
        int16_t* item = r + x * stride;
        decodeItem(codes, code, lanes, stride, x > 0 ? item - stride : nullptr, up ? item - row : nullptr,
                   x > 0 && up ? item - row - stride : nullptr, item);
    }
    return code;
}

// A w x h image of items with `lanes` planes each, stored `stride` (a multiple of 8, >= lanes)
// apart: the items of `runs` from their codes (item after item), every other item 0 (what the
// encoder left out). Returns the next code.
FIRELOOK_KERNEL_CLONES
size_t decodeImage(const CodeStream& codes, size_t first_code, int lanes, int stride, int w, int h,
                   const std::vector<Run>& runs, int16_t* out) {
    const size_t width = static_cast<size_t>(w), row = width * stride, items = width * h;
    size_t done = 0;  // items [0, done) are written
    for (const Run& run : runs) {
        std::memset(out + done * stride, 0, (run.first - done) * stride * sizeof(int16_t));
        const size_t end = run.first + run.count;
        for (size_t p = run.first; p < end;) {
            const size_t y = p / width, row_end = std::min(end, (y + 1) * width);
            first_code = decodeSegment(codes, first_code, lanes, stride, row, out + y * row, y > 0,
                                       p - y * width, row_end - y * width);
            p = row_end;
        }
        done = end;
    }
    std::memset(out + done * stride, 0, (items - done) * stride * sizeof(int16_t));
    return first_code;
}

// Indices among the detailed pixels (increasing) of one pixel row, by column (-1: not detailed).
// A lattice row's predictions read two pixel rows (its own and the one above), so two are kept;
// a table stays valid until the second table() call after it.
class DetailedRows {
  public:
    DetailedRows(std::span<const int32_t> detailed, int width) : detailed_(detailed), width_(width) {
        for (Row& r : rows_) r.index.resize(static_cast<size_t>(width));
    }
    // The detailed pixels of pixel row py: a contiguous run of the sorted list.
    std::pair<size_t, size_t> range(int py) const {
        const auto b = std::lower_bound(detailed_.begin(), detailed_.end(), py * width_);
        const auto e = std::lower_bound(b, detailed_.end(), (py + 1) * width_);
        return {static_cast<size_t>(b - detailed_.begin()), static_cast<size_t>(e - detailed_.begin())};
    }
    const int32_t* table(int py) {
        if (rows_[last_].row == py) return rows_[last_].index.data();
        last_ ^= 1;
        Row& r = rows_[last_];
        if (r.row != py) {
            r.row = py;
            std::fill(r.index.begin(), r.index.end(), -1);
            const auto [b, e] = range(py);
            for (size_t i = b; i < e; ++i) r.index[static_cast<size_t>(detailed_[i] - py * width_)] = static_cast<int32_t>(i);
        }
        return r.index.data();
    }

  private:
    struct Row {
        int row = -1;
        std::vector<int32_t> index;
    };
    std::span<const int32_t> detailed_;
    int width_;
    Row rows_[2];
    int last_ = 0;
};

// The detailed pixels' rays on the ray lattice (RayLattice), in its scan order: each ray is
// predicted from its lattice neighbours, which are rays of detailed pixels or else the mean ray
// of their pixel (what the encoder's plane held there). `detailed` increasing (their rays are
// stored in this order, `samples` each). Returns the next code.
FIRELOOK_KERNEL_CLONES
size_t decodeRays(const CodeStream& codes, size_t code, int lanes, const RayLattice& l, const int16_t* mean,
                  int stride, std::span<const int32_t> detailed, int16_t* rays) {
    if (detailed.empty()) return code;
    const int n = l.n, per_pixel = n > 0 ? n : 1, samples = l.samples(), width = l.image_width;
    DetailedRows rows(detailed, width);
    auto ray = [&](size_t index, int s) { return rays + (index * samples + s) * stride; };
    // Lattice row y is pixel row py and, within it, sub-row `sub` (n x n rays: the ray at column c
    // of the pixel is sample sub n + c) or sample `sub` (stacked images).
    auto pixelRow = [&](int y) { return n > 0 ? y / n : y % l.image_height; };
    auto subRow = [&](int y) { return n > 0 ? y % n : y / l.image_height; };
    auto sampleOf = [&](int sub, int c) { return n > 0 ? sub * n + c : sub; };
    for (int y = 0; y < l.height; ++y) {
        const int py = pixelRow(y), sub = subRow(y);
        const auto [first, end] = rows.range(py);
        if (first == end) continue;
        const int32_t* row = rows.table(py);
        const int up_py = y > 0 ? pixelRow(y - 1) : -1, up_sub = y > 0 ? subRow(y - 1) : 0;
        const int32_t* up_row = y > 0 ? rows.table(up_py) : nullptr;
        // The ray (or, not detailed, the mean ray) of pixel (column, row qy) and sample s.
        auto at = [&](const int32_t* table, int qy, int column, int s) -> const int16_t* {
            const int32_t index = table[column];
            return index >= 0 ? ray(static_cast<size_t>(index), s)
                              : mean + (static_cast<size_t>(qy) * width + column) * stride;
        };
        for (size_t index = first; index < end; ++index) {
            const int px = detailed[index] - py * width;
            for (int c = 0; c < per_pixel; ++c) {
                const int16_t *left = nullptr, *up = nullptr, *up_left = nullptr;
                if (c > 0)
                    left = ray(index, sampleOf(sub, c - 1));
                else if (px > 0)
                    left = at(row, py, px - 1, sampleOf(sub, per_pixel - 1));
                if (up_row) {
                    up = at(up_row, up_py, px, sampleOf(up_sub, c));
                    if (c > 0)
                        up_left = at(up_row, up_py, px, sampleOf(up_sub, c - 1));
                    else if (px > 0)
                        up_left = at(up_row, up_py, px - 1, sampleOf(up_sub, per_pixel - 1));
                }
                decodeItem(codes, code, lanes, stride, left, up, up_left, ray(index, sampleOf(sub, c)));
                code += static_cast<size_t>(lanes);
            }
        }
    }
    return code;
}

// Codes stored plane after plane (`planes` planes of `items` codes, as two byte planes) rewritten
// item after item, the order decodeImage reads.
struct TransposedCodes {
    std::vector<uint8_t> bytes;
    CodeStream stream;
    TransposedCodes(const uint8_t* lo, const uint8_t* hi, size_t planes, size_t items) : bytes(2 * planes * items) {
        const size_t count = planes * items;
        for (size_t j = 0; j < items; ++j)
            for (size_t k = 0; k < planes; ++k) {
                bytes[j * planes + k] = lo[k * items + j];
                bytes[count + j * planes + k] = hi[k * items + j];
            }
        stream = {bytes.data(), bytes.data() + count, count};
    }
};

// Depth planes as stored (q(O_b), e_0, then e_(j-1) - e_j) to the resident form (q(O_b), e_j):
// e_j = d_0 - d_1 - ... - d_j, a prefix sum over lanes 1..thresholds of the differences with
// their signs, 8 lanes at a time (three shift-and-add steps, then the previous block's carry).
FIRELOOK_KERNEL_CLONES
void accumulateThresholds(int16_t* items, size_t count, int stride, int thresholds) {
    constexpr int kMaxBlocks = 8;  // strides up to 64 lanes vectorised (thresholds <= 63)
    const int blocks = stride / 8;
    if (blocks > kMaxBlocks) {
        for (size_t i = 0; i < count; ++i) {
            int16_t* v = items + i * stride;
            int16_t e = v[1];
            for (int j = 1; j < thresholds; ++j) v[1 + j] = e = static_cast<int16_t>(e - v[1 + j]);
        }
        return;
    }
    v8s sign[kMaxBlocks];  // +1 for d_0, -1 for d_j (j >= 1), 0 for q(O_b) and the padding
    for (int b = 0; b < blocks; ++b)
        for (int l = 0; l < 8; ++l) {
            const int lane = 8 * b + l;
            sign[b][l] = static_cast<int16_t>(lane == 1 ? 1 : lane >= 2 && lane <= thresholds ? -1 : 0);
        }
    const v8s zero = {};
    for (size_t i = 0; i < count; ++i) {
        int16_t* v = items + i * stride;
        const int16_t q = v[0];
        int16_t carry = 0;
        for (int b = 0; b < blocks; ++b) {
            v8s x;
            simd::load(x, v + 8 * b);
            x *= sign[b];
            x += __builtin_shufflevector(x, zero, 8, 0, 1, 2, 3, 4, 5, 6);
            x += __builtin_shufflevector(x, zero, 8, 9, 0, 1, 2, 3, 4, 5);
            x += __builtin_shufflevector(x, zero, 8, 9, 10, 11, 0, 1, 2, 3);
            x += carry;
            carry = x[7];
            x = sign[b] != 0 ? x : zero;  // padding stays 0
            simd::store(v + 8 * b, x);
        }
        v[0] = q;
    }
}

int roundUp8(int n) { return (n + 7) / 8 * 8; }

// The runs a payload codes, as the resident form keeps them (pixel counts fit int32:
// bake_description.cpp bounds them).
void keepRuns(const std::vector<Run>& runs, std::pmr::vector<PixelRun>& out) {
    out.clear();
    for (const Run& run : runs) out.push_back({static_cast<int32_t>(run.first), static_cast<int32_t>(run.count)});
}

}  // namespace

namespace {

// The frame's shape, which every section's decoder sets.
void setShape(const BakeDescription& description, int frame, int rank, ResidentFrame& f) {
    f.frame = frame;
    f.pixels = description.pixelCount();
    f.columns = description.columnCount();
    f.rank = rank;
    f.rank_stride = roundUp8(rank);
    f.samples = description.footprint_samples;
}

std::string sectionName(const std::string& source, int frame, const char* section) {
    return source + ": frame " + std::to_string(frame) + " " + section + " section";
}

}  // namespace

void decodeResidentU(const BakeDescription& description, int frame, int rank, std::span<const std::byte> u,
                     const std::string& source, ResidentFrame& f) {
    setShape(description, frame, rank, f);
    const size_t pixels = static_cast<size_t>(f.pixels);
    ByteReader in(u, sectionName(source, frame, "UFAC"));
    const uint32_t version = in.get<uint32_t>();
    if (version < 1 || version > kCodecVersion) in.fail("has an unknown codec version");
    if (in.get<uint32_t>() != static_cast<uint32_t>(rank)) in.fail("holds another rank than the metadata");
    const double step = in.get<double>();
    if (!(step > 0.0) || !std::isfinite(step)) in.fail("has an invalid step");
    f.u_scale.assign(static_cast<size_t>(f.rank_stride), 0.0f);
    for (int k = 0; k < rank; ++k) {
        f.u_scale[k] = in.get<float>();
        if (!std::isfinite(f.u_scale[k])) in.fail("has a non-finite scale");
    }
    const std::vector<Run> runs = version >= 3 ? getRuns(in, pixels) : allItems(pixels);
    keepRuns(runs, f.u_runs);
    std::optional<ReorderedCodes> reordered;
    CodeStream codes;
    if (version == 1) {
        reordered.emplace(in, std::initializer_list<std::pair<size_t, size_t>>{{size_t(rank), pixels}});
        codes = reordered->stream;
    } else {
        codes = CodeStream::of(in, itemsIn(runs) * rank);
    }
    in.expectEnd();
    f.w.resize(pixels * f.rank_stride);  // every value is written below
    if (rank > 0)
        decodeImage(codes, 0, rank, f.rank_stride, description.width, description.height, runs, f.w.data());
    else
        std::fill(f.w.begin(), f.w.end(), int16_t{0});
}

void decodeResidentSvt(const BakeDescription& description, int frame, int rank, std::span<const std::byte> svt,
                       const std::string& source, ResidentFrame& f) {
    setShape(description, frame, rank, f);
    const size_t columns = static_cast<size_t>(f.columns), count = columns * rank;
    ByteReader in(svt, sectionName(source, frame, "SVTF"));
    const int kinds = description.columnsPerPoint();
    std::vector<double> steps(kinds, in.get<double>());  // versions 1-3: one step
    if (steps.empty() || steps[0] == kPerColumnSteps)
        for (double& s : steps) s = in.get<double>();
    for (double s : steps)
        if (!(s > 0.0) || !std::isfinite(s)) in.fail("has an invalid step");
    const auto* lo = reinterpret_cast<const uint8_t*>(in.need(count * 2));
    const uint8_t* hi = lo + count;
    in.expectEnd();
    f.svt.resize(count);
    if (rank == 0) return;
    // Plane-major codes item-major (a column's rank codes together), so that decodeImage undoes
    // the prediction of every plane at once; then to the column-major float layout.
    const TransposedCodes codes(lo, hi, static_cast<size_t>(rank), columns);
    const int stride = roundUp8(rank);
    std::vector<int16_t> items(columns * stride);
    decodeImage(codes.stream, 0, rank, stride, description.columnsPerPoint(), description.axes.pointCount(),
                allItems(columns), items.data());
    for (size_t j = 0; j < columns; ++j)
        for (int k = 0; k < rank; ++k) f.svt[j * rank + k] = static_cast<float>(items[j * stride + k] * steps[j % kinds]);
}

void decodeResidentDepths(const BakeDescription& description, int frame, int rank, std::span<const std::byte> depths,
                          const std::string& source, ResidentFrame& f) {
    setShape(description, frame, rank, f);
    std::shared_ptr<const DepthTable> table = std::move(f.depth_table);
    f.detailed_pixels.clear();
    const size_t pixels = static_cast<size_t>(f.pixels);
    ByteReader in(depths, sectionName(source, frame, "ODEP"));
    const uint32_t version = in.get<uint32_t>();
    if (version < 1 || version > kCodecVersion) in.fail("has an unknown codec version");
    const size_t thresholds = in.get<uint32_t>();
    if (thresholds != description.alpha_thresholds.size()) in.fail("holds another threshold count");
    const double step = in.get<double>();
    DepthCompanding g;
    g.k_lo = in.get<double>();
    g.k_hi = in.get<double>();
    if (!(step > 0.0) || !(g.k_lo > 0.0) || !(g.k_hi >= g.k_lo) || !std::isfinite(g.k_hi) ||
        depthLevels(g, step) > 32767.0)
        in.fail("has an invalid depth quantisation");
    f.depth_table = table && table->sameGrid(step, g.k_lo, g.k_hi) ? std::move(table)
                                                                    : DepthTable::build(step, g.k_lo, g.k_hi);
    const RayLattice lattice = RayLattice::of(description);
    const int planes = static_cast<int>(1 + thresholds);
    f.depth_stride = roundUp8(planes);
    std::vector<Run> runs;
    if (version >= 3) {
        runs = getRuns(in, pixels);
        // The detailed pixels (keep every ray), as gaps.
        const uint32_t detailed = in.get<uint32_t>();
        const std::byte* gaps = in.need(static_cast<size_t>(detailed) * 4);
        f.detailed_pixels.reserve(detailed);
        size_t next = 0;
        for (uint32_t i = 0; i < detailed; ++i) {
            uint32_t gap;
            std::memcpy(&gap, gaps + 4 * i, 4);
            if (gap >= pixels - next) in.fail("has an invalid detailed pixel");
            f.detailed_pixels.push_back(static_cast<int32_t>(next + gap));
            next += gap + 1;
        }
    } else {
        runs = allItems(pixels);
        // Which pixels are detailed, one flag each.
        const auto* flags = reinterpret_cast<const uint8_t*>(in.need(pixels));
        for (size_t p = 0; p < pixels; ++p) {
            if (flags[p] > 1) in.fail("has an invalid pixel flag");
            if (flags[p]) f.detailed_pixels.push_back(static_cast<int32_t>(p));
        }
    }
    keepRuns(runs, f.depth_runs);
    const size_t detailed_rays = f.detailed_pixels.size() * static_cast<size_t>(f.samples);
    std::optional<ReorderedCodes> reordered;
    CodeStream codes;
    if (version == 1) {
        reordered.emplace(in, std::initializer_list<std::pair<size_t, size_t>>{{size_t(planes), pixels},
                                                                              {size_t(planes), detailed_rays}});
        codes = reordered->stream;
    } else {
        codes = CodeStream::of(in, static_cast<size_t>(planes) * (itemsIn(runs) + detailed_rays));
    }
    in.expectEnd();
    f.mean_depth.resize(pixels * f.depth_stride);  // every value is written below
    f.detailed_depth.resize(detailed_rays * f.depth_stride);
    const size_t next =
        decodeImage(codes, 0, planes, f.depth_stride, description.width, description.height, runs, f.mean_depth.data());
    decodeRays(codes, next, planes, lattice, f.mean_depth.data(), f.depth_stride, f.detailed_pixels,
               f.detailed_depth.data());
    // The items left out are 0, which the sums keep.
    for (const Run& run : runs)
        accumulateThresholds(f.mean_depth.data() + run.first * f.depth_stride, run.count, f.depth_stride,
                             static_cast<int>(thresholds));
    accumulateThresholds(f.detailed_depth.data(), detailed_rays, f.depth_stride, static_cast<int>(thresholds));
}

void decodeResidentFrame(const BakeDescription& description, int frame, int rank, std::span<const std::byte> u,
                         std::span<const std::byte> svt, std::span<const std::byte> depths, const std::string& source,
                         ResidentFrame& f) {
    decodeResidentU(description, frame, rank, u, source, f);
    decodeResidentSvt(description, frame, rank, svt, source, f);
    decodeResidentDepths(description, frame, rank, depths, source, f);
}

ResidentFrame decodeResidentFrame(const BakeDescription& description, int frame, int rank,
                                  std::span<const std::byte> u, std::span<const std::byte> svt,
                                  std::span<const std::byte> depths, const std::string& source,
                                  std::pmr::memory_resource* memory, std::shared_ptr<const DepthTable> table) {
    ResidentFrame f(memory);
    f.depth_table = std::move(table);
    decodeResidentFrame(description, frame, rank, u, svt, depths, source, f);
    return f;
}

}  // namespace firelook::basis
