#include "basis/frame_codec.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/gtc/packing.hpp>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

#include "basis/simd.h"
#include "basis/source_balance.h"

namespace firelook::basis {
namespace {

// Payload version: 3 leaves out the items that are all zero (most pixels lie outside the fire's
// footprint), so neither zstd nor the decoder spends time on them; 2 stored every item's codes
// together (a pixel's rank values, a ray's depth planes), so the decoder undoes the prediction of
// all planes at once; 1 stored plane after plane. 4 stores one S V^T step per column of a grid
// point (each light source on its own grid, basis/source_balance.h); its UFAC and ODEP payloads
// are version 3's. All four are read.
constexpr uint32_t kCodecVersion = 4;
// What SVTF's first f64 holds from version 4 on, where versions 1-3 held the one step (a step of
// 0 is refused by them, so an older reader names the payload instead of misreading it).
constexpr double kPerColumnSteps = 0.0;
// U and S V^T share the basis error: each adds half of its square.
constexpr double kPerFactor = 0.70710678118654752;

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
    [[noreturn]] void fail(const std::string& problem) const { throw std::runtime_error(what_ + " " + problem); }

  private:
    std::span<const std::byte> bytes_;
    size_t at_ = 0;
    std::string what_;
};

// ---- prediction ------------------------------------------------------------------------------
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

// Residuals of a plane, appended to `codes` in scan order; with a mask, only where it is 1 (the
// other values are known to the decoder already and still serve as neighbours).
void predictPlane(const int16_t* values, int w, int h, const uint8_t* mask, std::vector<uint16_t>& codes) {
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t i = static_cast<size_t>(y) * w + x;
            if (mask && !mask[i]) continue;
            codes.push_back(zigzag(static_cast<int16_t>(values[i] - predictAt(values, x, y, w))));
        }
}

// Codes as two byte planes (all low bytes, then all high bytes): most high bytes are 0, which
// zstd then stores as one long run.
void putShuffled(ByteWriter& out, const std::vector<uint16_t>& codes) {
    std::byte* p = out.grow(codes.size() * 2);
    for (size_t i = 0; i < codes.size(); ++i) {
        p[i] = static_cast<std::byte>(codes[i] & 0xFF);
        p[codes.size() + i] = static_cast<std::byte>(codes[i] >> 8);
    }
}

// Occupied items (scan order) as runs: u32 count, then per run u32 gap (items since the end of
// the previous run) and u32 length. A blob-shaped footprint takes a few runs per row.
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

// Items whose planes (plane-major, `items` values each) are all 0.
std::vector<uint8_t> occupiedItems(const int16_t* planes, size_t count, size_t items) {
    std::vector<uint8_t> occupied(items, 0);
    for (size_t i = 0; i < count; ++i)
        for (size_t j = 0; j < items; ++j) occupied[j] |= planes[i * items + j] != 0;
    return occupied;
}

// Plane-major codes (plane after plane, `items` codes each) to item-major (an item's `planes`
// codes together), the order version 2 stores; `transpose(codes, items, planes)` is the inverse.
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

// ---- ray lattice -----------------------------------------------------------------------------
// Footprint ray s of pixel p, for n x n cell-centred rays, sits at (px n + s % n, py n + s / n)
// of a lattice n times finer than the image, so neighbouring rays (of one pixel or of two) are
// neighbours there. A footprint that is not square keeps one image per ray, stacked.
struct RayLattice {
    int width = 0, height = 0;
    int n = 0;  // rays per axis; 0 = stacked images
    int image_width = 0, image_height = 0;

    static RayLattice of(const BakeDescription& d) {
        RayLattice l;
        l.image_width = d.width;
        l.image_height = d.height;
        const int n = static_cast<int>(std::lround(std::sqrt(static_cast<double>(d.footprint_samples))));
        if (n * n == d.footprint_samples) {
            l.n = n;
            l.width = d.width * n;
            l.height = d.height * n;
        } else {
            l.width = d.width;
            l.height = d.height * d.footprint_samples;
        }
        return l;
    }
    size_t size() const { return static_cast<size_t>(width) * height; }
    int samples() const { return n > 0 ? n * n : height / std::max(image_height, 1); }
    // A per-pixel value on every ray of the pixel.
    std::vector<uint8_t> spread(const std::vector<uint8_t>& per_pixel) const {
        std::vector<uint8_t> out(size());
        for (int s = 0; s < samples(); ++s)
            for (size_t p = 0; p < per_pixel.size(); ++p) out[at(s, p)] = per_pixel[p];
        return out;
    }
    // Lattice index of ray (sample s, pixel p).
    size_t at(int s, size_t p) const {
        if (n == 0) return static_cast<size_t>(s) * image_width * image_height + p;
        const size_t px = p % image_width, py = p / image_width;
        return (py * n + s / n) * width + px * n + s % n;
    }
};

// Which pixels keep all their footprint rays: those whose alpha, for some look on or between the
// grid points (every threshold sample, each k axis's samples and their geometric midpoints),
// differs by more than `tolerance` from the alpha of their mean ray. Elsewhere the footprint
// is smooth enough that the mean ray stands for it (Jensen's gap, mean e^-tau - e^-mean tau,
// is second order in the spread of tau).
class FootprintTest {
  public:
    FootprintTest(const BakeDescription& d, double tolerance) : tolerance_(tolerance) {
        auto withMidpoints = [](const std::vector<double>& axis) {
            std::vector<double> out;
            for (size_t i = 0; i < axis.size(); ++i) {
                out.push_back(axis[i]);
                if (i + 1 < axis.size()) out.push_back(axis[i] > 0.0 ? std::sqrt(axis[i] * axis[i + 1]) : 0.5 * axis[i + 1]);
            }
            return out;
        };
        k_s_ = withMidpoints(d.axes.smoke_extinction);
        k_f_ = withMidpoints(d.axes.flame_extinction);
    }
    bool needsRays(const std::vector<double>& o, const std::vector<double>& smoke, double mean_o,
                   const std::vector<double>& mean_smoke) const {
        const size_t samples = o.size(), thresholds = mean_smoke.size();
        bool uniform = true;
        for (size_t s = 1; s < samples && uniform; ++s) uniform = o[s] == o[0];
        for (size_t i = thresholds; i < smoke.size() && uniform; ++i) uniform = smoke[i] == smoke[i % thresholds];
        if (uniform) return false;
        if (!(tolerance_ > 0.0)) return true;
        for (size_t j = 0; j < thresholds; ++j)
            for (double ks : k_s_)
                for (double kf : k_f_) {
                    double sum = 0.0;
                    for (size_t s = 0; s < samples; ++s) sum += std::exp(-(kf * o[s] + (ks - kf) * smoke[s * thresholds + j]));
                    const double gap = sum / samples - std::exp(-(kf * mean_o + (ks - kf) * mean_smoke[j]));
                    if (std::abs(gap) > tolerance_) return true;
                }
        return false;
    }

  private:
    double tolerance_;
    std::vector<double> k_s_, k_f_;
};

// The step of a uniform grid on which rounding `count` values adds a Frobenius error of about
// `target` (step^2 / 12 per value), coarsened so that the largest value fits an int16.
double uniformGridStep(double target, double count, double largest) {
    double step = target / std::sqrt(std::max(1.0, count / 12.0));
    step = std::max(step, largest / 32767.0);
    return step > 0.0 ? step : 1.0;  // nothing to store: any step
}

// A stored factor's value, 0 where it is not finite (no NaN reaches a grid).
double finiteOrZero(float v) { return std::isfinite(v) ? v : 0.0; }

// x on that grid, adding its squared rounding error to `error2`.
int16_t onGrid(double x, double step, double& error2) {
    const double q = std::clamp(std::round(x / step), -32767.0, 32767.0);
    error2 += (q * step - x) * (q * step - x);
    return static_cast<int16_t>(q);
}

// Levels of the depth grid, rounded up so that rounding g(O) / step is within half a step even for
// the deepest rays (the top level may decode to +inf, stored as kLargestDepth).
double depthLevels(const DepthCompanding& g, double step) { return std::ceil(g.limit() / step); }

}  // namespace

// ---- depth companding ------------------------------------------------------------------------
// g'(x) = max over k in [k_lo, k_hi] of k e^(-k x): k_hi e^(-k_hi x) below 1/k_hi, 1/(e x) up to
// 1/k_lo (the maximum is at k = 1/x), k_lo e^(-k_lo x) beyond. Its integral, piece by piece:
//   x <= 1/k_hi:         1 - e^(-k_hi x)
//   1/k_hi < x <= 1/k_lo: (1 - 1/e) + ln(k_hi x) / e
//   x > 1/k_lo:          (1 - 1/e) + ln(k_hi / k_lo) / e + 1/e - e^(-k_lo x)
// Why this bounds alpha: write tau = k_f O_b + (k_s - k_f) S with S = O_b - F the smoke part.
// If k_s >= k_f, tau >= k_f O_b and tau >= k_s S, so |d alpha / d O_b| <= k_f e^(-k_f O_b) <=
// g'(O_b) and |d alpha / d S| <= k_s e^(-k_s S) <= g'(S). If k_s < k_f, tau >= k_s O_b >= k_s S
// and both derivatives are at most k_f e^(-k_s x) <= (k_f / k_s) g'(x). So a change dg of
// g(O_b) and of g(S) moves a ray's alpha by at most c (|dg(O_b)| + |dg(S)|) with
// c = max(1, max k_f / min k_s), and a pixel's alpha (a mean of rays, linear in T_c between the
// threshold samples) by no more.
DepthCompanding DepthCompanding::forAxes(const ParameterAxes& axes) {
    DepthCompanding c;
    const auto [ks_lo, ks_hi] = std::minmax_element(axes.smoke_extinction.begin(), axes.smoke_extinction.end());
    const auto [kf_lo, kf_hi] = std::minmax_element(axes.flame_extinction.begin(), axes.flame_extinction.end());
    c.k_hi = std::max({*ks_hi, *kf_hi, 1e-6});
    // A zero extinction makes alpha independent of the depth it multiplies; the floor keeps the
    // companding finite, and for k below it the bound grows by at most k_lo |dO| (negligible).
    c.k_lo = std::max(std::min(*ks_lo, *kf_lo), c.k_hi * 1e-4);
    c.k_s_lo = std::max(*ks_lo, c.k_lo);
    c.k_f_hi = *kf_hi;
    return c;
}

double DepthCompanding::limit() const { return 1.0 + std::log(k_hi / k_lo) / M_E; }

double DepthCompanding::alphaFactor() const { return std::max(1.0, k_f_hi / k_s_lo); }

double DepthCompanding::forward(double x) const {
    if (!(x > 0.0)) return 0.0;
    if (x <= 1.0 / k_hi) return -std::expm1(-k_hi * x);
    const double first = 1.0 - 1.0 / M_E;
    if (x <= 1.0 / k_lo) return first + std::log(k_hi * x) / M_E;
    return first + std::log(k_hi / k_lo) / M_E + 1.0 / M_E - std::exp(-k_lo * x);
}

double DepthCompanding::inverse(double y) const {
    if (!(y > 0.0)) return 0.0;
    const double first = 1.0 - 1.0 / M_E;
    if (y <= first) return -std::log1p(-y) / k_hi;
    const double second = first + std::log(k_hi / k_lo) / M_E;
    if (y <= second) return std::exp((y - first) * M_E) / k_hi;
    const double rest = 1.0 / M_E - (y - second);
    return rest > 0.0 ? -std::log(rest) / k_lo : std::numeric_limits<double>::infinity();
}

// ---- encoding --------------------------------------------------------------------------------
EncodedFrame encodeFrame(const BakeDescription& description, const FrameFactors& factors,
                         const FrameCodecSettings& settings) {
    const size_t pixels = static_cast<size_t>(description.pixelCount());
    const int rank = factors.rank;
    const int samples = description.footprint_samples;
    const size_t thresholds = description.alpha_thresholds.size();
    const size_t rays = pixels * static_cast<size_t>(std::max(samples, 0));
    if (factors.pixels != static_cast<int>(pixels) || rank < 0 || factors.u_half.size() != pixels * rank ||
        factors.svt.size() != static_cast<size_t>(description.columnCount()) * rank || samples < 1 ||
        thresholds == 0 || factors.depth_b.size() != rays || factors.depth_a.size() != rays * thresholds)
        throw std::invalid_argument("frame " + std::to_string(factors.frame) +
                                    ": factor sizes do not match the description");
    if (!(settings.alpha_error > 0.0) || !(settings.basis_error > 0.0))
        throw std::invalid_argument("frame codec: error bounds must be positive");
    EncodedFrame out;

    // Both factors are measured on the basis with its sources balanced, B D (basis/source_balance.h).
    const size_t columns = static_cast<size_t>(description.columnCount());
    const int kinds = description.columnsPerPoint();
    const std::vector<double> balance = svtSourceBalance(factors.svt, rank, kinds, description.bins.count);

    // U as W = U S on one grid, S the singular values of B D: the norms of the rows of S V^T D
    // (V is orthonormal).
    {
        std::vector<double> sigma(rank, 0.0);
        for (size_t j = 0; j < columns; ++j)
            for (int k = 0; k < rank; ++k) {
                const double v = finiteOrZero(factors.svt[j * rank + k]) * balance[j % kinds];
                sigma[k] += v * v;
            }
        double norm2 = 0.0, largest = 0.0;
        for (int k = 0; k < rank; ++k) {
            sigma[k] = std::sqrt(sigma[k]);
            norm2 += sigma[k] * sigma[k];
        }
        std::vector<float> u(factors.u_half.size());
        for (size_t i = 0; i < u.size(); ++i) {
            const float v = glm::unpackHalf1x16(factors.u_half[i]);
            u[i] = std::isfinite(v) ? v : 0.0f;
            largest = std::max(largest, std::abs(u[i] * sigma[i % std::max(rank, 1)]));
        }
        const double step =
            uniformGridStep(kPerFactor * settings.basis_error * std::sqrt(norm2), double(pixels) * rank, largest);
        out.u_step = step;
        ByteWriter w;
        w.put<uint32_t>(kCodecVersion);
        w.put<uint32_t>(static_cast<uint32_t>(rank));
        w.put<double>(step);
        std::vector<float> scale(rank);
        for (int k = 0; k < rank; ++k) {
            scale[k] = sigma[k] > 0.0 ? static_cast<float>(step / sigma[k]) : 0.0f;
            w.put<float>(scale[k]);
        }
        std::vector<int16_t> planes(pixels * rank);
        double error2 = 0.0;
        for (int k = 0; k < rank; ++k)
            for (size_t p = 0; p < pixels; ++p)
                planes[k * pixels + p] = onGrid(double(u[p * rank + k]) * sigma[k], step, error2);
        out.u_error = norm2 > 0.0 ? std::sqrt(error2 / norm2) : 0.0;
        // Pixels whose W row is all 0 are left out (the decoder knows them from the runs).
        const std::vector<uint8_t> occupied = occupiedItems(planes.data(), rank, pixels);
        putRuns(w, occupied);
        std::vector<uint16_t> codes;
        codes.reserve(pixels * rank);
        for (int k = 0; k < rank; ++k)
            predictPlane(planes.data() + k * pixels, description.width, description.height, occupied.data(), codes);
        putShuffled(w, transpose(codes.data(), rank, rank > 0 ? codes.size() / rank : 0));
        out.u = w.take();
    }

    // S V^T D on one grid, so S V^T with one step per column kind (the grid's step over that kind's
    // factor): ||d(B D)||_F = ||U d(S V^T D)||_F = ||d(S V^T D)||_F. Per coefficient k, the
    // columns form an image of (bins + lights) x grid points, whose neighbours are alike.
    {
        double norm2 = 0.0, largest = 0.0;
        for (size_t j = 0; j < columns; ++j)
            for (int k = 0; k < rank; ++k) {
                const double x = finiteOrZero(factors.svt[j * rank + k]) * balance[j % kinds];
                norm2 += x * x;
                largest = std::max(largest, std::abs(x));
            }
        const double step =
            uniformGridStep(kPerFactor * settings.basis_error * std::sqrt(norm2), double(columns) * rank, largest);
        out.svt_step = step;
        std::vector<double> steps(kinds);
        for (int c = 0; c < kinds; ++c) steps[c] = step / balance[c];
        ByteWriter w;
        w.put<double>(kPerColumnSteps);
        for (double s : steps) w.put<double>(s);
        std::vector<int16_t> plane(columns);
        std::vector<uint16_t> codes;
        codes.reserve(columns * rank);
        double error2 = 0.0;  // in B D
        for (int k = 0; k < rank; ++k) {
            for (size_t j = 0; j < columns; ++j) {
                double cell_error2 = 0.0;
                plane[j] = onGrid(finiteOrZero(factors.svt[j * rank + k]), steps[j % kinds], cell_error2);
                error2 += cell_error2 * balance[j % kinds] * balance[j % kinds];
            }
            predictPlane(plane.data(), description.columnsPerPoint(), description.axes.pointCount(), nullptr, codes);
        }
        out.svt_error = norm2 > 0.0 ? std::sqrt(error2 / norm2) : 0.0;
        putShuffled(w, codes);
        out.svt = w.take();
    }

    // Depths (see "Optical depths" in docs/package-format.md).
    {
        const DepthCompanding g = DepthCompanding::forAxes(description.axes);
        // c (|dg_O| + |dg_S|) <= c step per ray. A step finer than 2^15 levels allow (an axis
        // reaching k_s = 0 makes c huge: the flame part then rests on O_b - S alone) takes the
        // finest grid there is, and the bound reported is what that grid gives.
        double step = settings.alpha_error / g.alphaFactor();
        if (depthLevels(g, step) > 32767.0) step = g.limit() / 32767.0;
        const double levels = depthLevels(g, step);
        out.alpha_bound = std::min(1.0, step * g.alphaFactor() + std::max(0.0, settings.footprint_error));
        const RayLattice lattice = RayLattice::of(description);
        auto quantise = [&](double depth) {
            return static_cast<int16_t>(std::min(levels, std::round(g.forward(depth) / step)));
        };
        // Per ray: O_b (NaN: opaque, as layout 1 did) and the smoke parts S_j = O_b - F_j.
        auto rayDepths = [&](int s, size_t p, double* smoke) {
            const double density = factors.depth_b[static_cast<size_t>(s) * pixels + p];
            const double d = std::isnan(density) ? kLargestDepth : std::clamp(density, 0.0, double(kLargestDepth));
            for (size_t j = 0; j < thresholds; ++j) {
                const double o_a = factors.depth_a[(static_cast<size_t>(s) * thresholds + j) * pixels + p];
                smoke[j] = d - (std::isfinite(o_a) ? std::clamp(0.5 * (o_a + d), 0.0, d) : 0.0);
            }
            return d;
        };
        const FootprintTest footprint(description, settings.footprint_error);
        // Planes: 0 = q(O_b), 1 = e_0, 1 + j = e_(j-1) - e_j, with e_j = q(O_b) - q(S_j) (0 where no
        // flame is crossed); for the mean ray of every pixel (image) and for every ray (lattice).
        const size_t planes = 1 + thresholds;
        std::vector<int16_t> mean(planes * pixels), rays_q(planes * lattice.size());
        std::vector<uint8_t> detailed(pixels, 0);
        std::vector<double> o(samples), smoke(static_cast<size_t>(samples) * thresholds), mean_smoke(thresholds);
        auto toPlanes = [&](double o_b, const double* s_j, int16_t* dst, size_t stride) {
            const int16_t qo = quantise(o_b);
            dst[0] = qo;
            int16_t previous = 0;
            for (size_t j = 0; j < thresholds; ++j) {
                const int16_t e = static_cast<int16_t>(qo - std::min<int>(qo, quantise(s_j[j])));
                dst[(1 + j) * stride] = j == 0 ? e : static_cast<int16_t>(previous - e);
                previous = e;
            }
        };
        for (size_t p = 0; p < pixels; ++p) {
            double mean_o = 0.0;
            std::fill(mean_smoke.begin(), mean_smoke.end(), 0.0);
            for (int s = 0; s < samples; ++s) {
                o[s] = rayDepths(s, p, smoke.data() + static_cast<size_t>(s) * thresholds);
                mean_o += o[s] / samples;
                for (size_t j = 0; j < thresholds; ++j) mean_smoke[j] += smoke[s * thresholds + j] / samples;
            }
            toPlanes(mean_o, mean_smoke.data(), mean.data() + p, pixels);
            for (int s = 0; s < samples; ++s)
                toPlanes(o[s], smoke.data() + static_cast<size_t>(s) * thresholds, rays_q.data() + lattice.at(s, p),
                         lattice.size());
            detailed[p] = footprint.needsRays(o, smoke, mean_o, mean_smoke) ? 1 : 0;
        }
        ByteWriter w;
        w.put<uint32_t>(kCodecVersion);
        w.put<uint32_t>(static_cast<uint32_t>(thresholds));
        w.put<double>(step);
        w.put<double>(g.k_lo);
        w.put<double>(g.k_hi);
        // Pixels whose mean ray is all 0 (no depth at all) are left out of the mean rays' codes.
        const std::vector<uint8_t> occupied = occupiedItems(mean.data(), planes, pixels);
        putRuns(w, occupied);
        // The detailed pixels: u32 count, then each as u32 gap from the one before (+1).
        w.put<uint32_t>(static_cast<uint32_t>(std::count(detailed.begin(), detailed.end(), uint8_t{1})));
        for (size_t p = 0, next = 0; p < pixels; ++p)
            if (detailed[p]) {
                w.put<uint32_t>(static_cast<uint32_t>(p - next));
                next = p + 1;
            }
        // A pixel without detail has all its rays equal to its mean ray.
        const std::vector<uint8_t> ray_detailed = lattice.spread(detailed);
        for (size_t i = 0; i < planes; ++i)
            for (int s = 0; s < samples; ++s)
                for (size_t p = 0; p < pixels; ++p)
                    if (!detailed[p]) rays_q[i * lattice.size() + lattice.at(s, p)] = mean[i * pixels + p];
        std::vector<uint16_t> mean_codes, ray_codes;
        mean_codes.reserve(planes * pixels);
        for (size_t i = 0; i < planes; ++i)
            predictPlane(mean.data() + i * pixels, description.width, description.height, occupied.data(), mean_codes);
        for (size_t i = 0; i < planes; ++i)
            predictPlane(rays_q.data() + i * lattice.size(), lattice.width, lattice.height, ray_detailed.data(),
                         ray_codes);
        std::vector<uint16_t> codes = transpose(mean_codes.data(), planes, mean_codes.size() / planes);
        const std::vector<uint16_t> rays_item_major = transpose(ray_codes.data(), planes, ray_codes.size() / planes);
        codes.insert(codes.end(), rays_item_major.begin(), rays_item_major.end());
        putShuffled(w, codes);
        out.depths = w.take();
        out.detailed_pixels = static_cast<size_t>(std::count(detailed.begin(), detailed.end(), uint8_t{1}));
    }
    return out;
}

FrameFactors emptyFrameFactors(const BakeDescription& description, int frame, int rank) {
    FrameFactors f;
    f.frame = frame;
    f.pixels = description.pixelCount();
    f.columns = description.columnCount();
    f.rank = rank;
    return f;
}

// ---- decoding --------------------------------------------------------------------------------
std::shared_ptr<const DepthTable> DepthTable::build(double step, double k_lo, double k_hi) {
    auto table = std::make_shared<DepthTable>();
    table->step = step;
    table->k_lo = k_lo;
    table->k_hi = k_hi;
    DepthCompanding g;
    g.k_lo = k_lo;
    g.k_hi = k_hi;
    const int levels = static_cast<int>(depthLevels(g, step)) + 1;
    table->depth.resize(levels);
    for (int q = 0; q < levels; ++q)
        table->depth[q] = static_cast<float>(std::min(double(kLargestDepth), g.inverse(q * step)));
    return table;
}

namespace {
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

// The median edge detector (medPredict) on 8 or 16 planes at once; the sums wrap as int16
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

FrameFactors expandFrame(const BakeDescription& description, const ResidentFrame& r) {
    FrameFactors f = emptyFrameFactors(description, r.frame, r.rank);
    const size_t pixels = static_cast<size_t>(f.pixels);
    f.u_half.resize(pixels * r.rank);
    for (size_t p = 0; p < pixels; ++p)
        for (int k = 0; k < r.rank; ++k)
            f.u_half[p * r.rank + k] = glm::packHalf1x16(r.w[p * r.rank_stride + k] * r.u_scale[k]);
    f.svt.assign(r.svt.begin(), r.svt.end());
    const size_t thresholds = description.alpha_thresholds.size();
    const int samples = description.footprint_samples;
    f.depth_b.resize(pixels * samples);
    f.depth_a.resize(pixels * samples * thresholds);
    const std::vector<float>& table = r.depth_table->depth;
    const int last = static_cast<int>(table.size()) - 1;
    auto depth = [&](int q) { return table[static_cast<size_t>(std::clamp(q, 0, last))]; };
    size_t next_detailed = 0;
    for (size_t p = 0; p < pixels; ++p) {
        const bool detailed =
            next_detailed < r.detailed_pixels.size() && static_cast<size_t>(r.detailed_pixels[next_detailed]) == p;
        for (int s = 0; s < samples; ++s) {
            const int16_t* v = detailed ? r.detailed_depth.data() + (next_detailed * samples + s) * r.depth_stride
                                        : r.mean_depth.data() + p * r.depth_stride;
            const float o_b = depth(v[0]);
            f.depth_b[static_cast<size_t>(s) * pixels + p] = o_b;
            // O_a = 2 F - O_b = O_b - 2 S.
            for (size_t j = 0; j < thresholds; ++j)
                f.depth_a[(static_cast<size_t>(s) * thresholds + j) * pixels + p] =
                    o_b - 2.0f * depth(int(v[0]) - int(v[1 + j]));
        }
        if (detailed) ++next_detailed;
    }
    return f;
}

FrameFactors decodeFrame(const BakeDescription& description, int frame, int rank, std::span<const std::byte> u,
                         std::span<const std::byte> svt, std::span<const std::byte> depths,
                         const std::string& source) {
    return expandFrame(description,
                       decodeResidentFrame(description, frame, rank, u, svt, depths, source,
                                           std::pmr::get_default_resource(), nullptr));
}

}  // namespace firelook::basis
