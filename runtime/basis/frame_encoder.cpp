// The frame codec's encoder (frame_codec.h): quantises, predicts and writes the three payloads.
#include <algorithm>
#include <cmath>
#include <glm/gtc/packing.hpp>
#include <stdexcept>
#include <string>

#include "basis/codec_streams.h"
#include "basis/depth_companding.h"
#include "basis/frame_codec.h"
#include "basis/ray_lattice.h"
#include "basis/source_balance.h"
#include "common/error.h"

namespace firelook::basis {
namespace {

using codec::ByteWriter;
using codec::kCodecVersion;
using codec::kPerColumnSteps;
using codec::occupiedItems;
using codec::predictPlane;
using codec::putRuns;
using codec::putShuffled;
using codec::RayLattice;
using codec::transpose;

// U and S V^T share the basis error: each adds half of its square.
constexpr double kPerFactor = 0.70710678118654752;

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
                   const std::vector<double>& mean_smoke) {
        const size_t samples = o.size(), thresholds = mean_smoke.size();
        bool uniform = true;
        for (size_t s = 1; s < samples && uniform; ++s) uniform = o[s] == o[0];
        for (size_t i = thresholds; i < smoke.size() && uniform; ++i) uniform = smoke[i] == smoke[i % thresholds];
        if (uniform) return false;
        if (!(tolerance_ > 0.0)) return true;
        // A ray's transmittance exp(-(k_f O + (k_s - k_f) S)) is exp(-k_f (O - S)) exp(-k_s S): one
        // exponential per sample of each axis instead of one per pair of them (the exponentials were
        // most of a frame's encoding, which runs on one core).
        const size_t n_s = k_s_.size(), n_f = k_f_.size();
        smoke_factor_.resize((samples + 1) * n_s);
        flame_factor_.resize((samples + 1) * n_f);
        for (size_t j = 0; j < thresholds; ++j) {
            for (size_t s = 0; s <= samples; ++s) {  // s == samples: the mean ray
                const double o_s = s < samples ? o[s] : mean_o;
                const double smoke_s = s < samples ? smoke[s * thresholds + j] : mean_smoke[j];
                for (size_t a = 0; a < n_s; ++a) smoke_factor_[s * n_s + a] = std::exp(-k_s_[a] * smoke_s);
                for (size_t a = 0; a < n_f; ++a) flame_factor_[s * n_f + a] = std::exp(-k_f_[a] * (o_s - smoke_s));
            }
            for (size_t a = 0; a < n_s; ++a)
                for (size_t b = 0; b < n_f; ++b) {
                    double sum = 0.0;
                    for (size_t s = 0; s < samples; ++s) sum += smoke_factor_[s * n_s + a] * flame_factor_[s * n_f + b];
                    const double gap = sum / samples - smoke_factor_[samples * n_s + a] * flame_factor_[samples * n_f + b];
                    if (std::abs(gap) > tolerance_) return true;
                }
        }
        return false;
    }

  private:
    double tolerance_;
    std::vector<double> k_s_, k_f_;
    std::vector<double> smoke_factor_, flame_factor_;  // per sample and axis value, the mean ray last
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


}  // namespace

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
        throw Error(ErrorCode::InvalidArgument,
                    "frame " + std::to_string(factors.frame) + ": factor sizes do not match the description");
    if (!(settings.alpha_error > 0.0) || !(settings.basis_error > 0.0))
        throw Error(ErrorCode::InvalidArgument, "frame codec: error bounds must be positive");
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
        FootprintTest footprint(description, settings.footprint_error);
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

}  // namespace firelook::basis
