#include "bake/camera_quadrature.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>
#include <optional>

#include "render/random.h"

namespace firelook::bake {
namespace {

// What a look sees of one pixel's quadrature error, per grid point: the emission bins summed and each
// light's column alone. A look's coefficients vary smoothly over the bins, and a footprint's error
// moves light between neighbouring bins, so bin by bin it is several times larger than any look's:
// frame 3 of the bundled sample at 128x128 with 3 of 4 rays, 2.2% over every column against 0.28%
// over the summed bins (frame 12 with 2 of 4: 0.62% over every column, median column 4.4%, worst
// 12.7%, its default look 0.22% against 8x8 rays). diff2 += the squared differences, value2 += the
// squares of the fine row.
void quadratureCheck(const float* row, const float* fine, int points, int columns, int bins, double& diff2,
                     double& value2) {
    for (int g = 0; g < points; ++g) {
        const float* r = row + static_cast<std::size_t>(g) * columns;
        const float* f = fine + static_cast<std::size_t>(g) * columns;
        double emission_row = 0.0, emission_fine = 0.0;
        for (int c = 0; c < bins; ++c) {
            emission_row += r[c];
            emission_fine += f[c];
        }
        diff2 += (emission_row - emission_fine) * (emission_row - emission_fine);
        value2 += emission_fine * emission_fine;
        for (int c = bins; c < columns; ++c) {
            diff2 += (double(r[c]) - f[c]) * (double(r[c]) - f[c]);
            value2 += double(f[c]) * f[c];
        }
    }
}

// sums[g * (1 + lights) + s] += per grid point g, the row's emission bins summed (s = 0) and each
// light's column (s = 1 + light): what a look sees of a pixel, as quadratureCheck counts it.
void addSourceSums(const float* row, int points, int columns, int bins, double* sums) {
    const int sources = 1 + columns - bins;
    for (int g = 0; g < points; ++g) {
        const float* r = row + static_cast<std::size_t>(g) * columns;
        double* to = sums + static_cast<std::size_t>(g) * sources;
        for (int c = 0; c < bins; ++c) to[0] += r[c];
        for (int c = bins; c < columns; ++c) to[1 + c - bins] += r[c];
    }
}

// Per-row sums of squared differences and squared values, summed over the rows in order:
// sqrt(sum diff^2 / sum value^2).
double relativeFrobeniusError(const std::vector<double>& diff2, const std::vector<double>& value2) {
    double d = 0.0, v = 0.0;
    for (std::size_t i = 0; i < diff2.size(); ++i) {
        d += diff2[i];
        v += value2[i];
    }
    return v > 0.0 ? std::sqrt(d / v) : 0.0;
}

// The largest difference of the pixel's alpha = mean over its rays of 1 - exp(-(a O_a + b O_b))
// between two sets of its rays' depths, over every look on the axes' samples (a = (k_f - k_s) / 2,
// b = (k_f + k_s) / 2 at each alpha threshold: docs/model.md).
double worstAlphaChange(const TraceTables& tb, int rays, const double* b0, const double* a0, const double* b1,
                        const double* a1) {
    double worst = 0.0;
    for (int t = 0; t < tb.n_alpha; ++t)
        for (float ks : tb.ks)
            for (float kf : tb.kf) {
                const double a = 0.5 * (double(kf) - ks), b = 0.5 * (double(kf) + ks);
                double sum = 0.0;
                for (int r = 0; r < rays; ++r)
                    sum += std::exp(-(a * a1[r * tb.n_alpha + t] + b * b1[r])) -
                           std::exp(-(a * a0[r * tb.n_alpha + t] + b * b0[r]));
                worst = std::max(worst, std::fabs(sum) / rays);
            }
    return worst;
}

// Pixel (px, py)'s m x m rays as the camera pass marches them: `to` += their radiance (after
// beginPixel); with depth_b and depth_a, their optical depths too (0 for a ray that misses the
// volume), in depth_b[ray] and depth_a[ray * n_alpha + threshold].
void gatherRays(CameraMarch& ray_march, const std::vector<float>& lbar_sum, int width, int px, int py, int m,
                float* to, int n_alpha, double* depth_b, double* depth_a) {
    const float weight = 1.0f / static_cast<float>(m * m);
    const std::size_t pixel = static_cast<std::size_t>(py) * width + px;
    for (int ray = 0; ray < m * m; ++ray) {
        double* ray_b = depth_b ? depth_b + ray : nullptr;
        double* ray_a = depth_a ? depth_a + ray * n_alpha : nullptr;
        if (ray_b) {
            *ray_b = 0.0;
            std::fill(ray_a, ray_a + n_alpha, 0.0);
        }
        ray_march.marchPixelRay(px, py, (ray % m + 0.5) / m, (ray / m + 0.5) / m, m, weight, ray_b, ray_a,
                                cameraRayPhase(pixel, ray));
    }
    addGathered(ray_march, lbar_sum, to);
}

// Each column's sum over the rows, in row order (rows nobody checked are empty).
std::vector<double> rowTotals(const std::vector<std::vector<double>>& rows, std::size_t columns) {
    std::vector<double> total(columns, 0.0);
    for (const std::vector<double>& row : rows)
        for (std::size_t k = 0; k < row.size(); ++k) total[k] += row[k];
    return total;
}

// A march of the check's rays at step_scale times the smallest step.
std::unique_ptr<CameraMarch> cameraMarch(const CameraQuadratureInputs& in, int step_scale) {
    return std::make_unique<CameraMarch>(in.medium, in.tables, in.cells, in.light_depths, in.camera,
                                         step_scale * in.min_step, in.footprint_step, !in.lbar_sum.empty());
}

}  // namespace

double cameraRayPhase(std::size_t pixel, int ray) {
    // "cameraph" in ASCII: fixed, whatever the photons' seed.
    constexpr std::uint64_t kPhaseStream = 0x63616d6572617068ULL;
    return 1.0 - render::Pcg32::forSample(kPhaseStream, pixel, static_cast<std::uint64_t>(ray)).uniform();
}

void addGathered(const CameraMarch& ray_march, const std::vector<float>& lbar_sum, float* to) {
    ray_march.addDirect(to);
    if (!lbar_sum.empty()) ray_march.contract(lbar_sum, to);
}

void gatherRadianceRays(CameraMarch& ray_march, const std::vector<float>& lbar_sum, int width, int px, int py,
                        int m, float* to) {
    gatherRays(ray_march, lbar_sum, width, px, py, m, to, 0, nullptr, nullptr);
}

int stepCheckStride(int width, int height) {
    const double per_axis = std::sqrt(double(width) * height / kStepCheckPixels);
    return std::clamp(static_cast<int>(per_axis), 1, kQuadratureCheckStride * 2);
}

CameraQuadrature chooseCameraQuadrature(const CameraQuadratureInputs& in, const QuadratureOptions& options,
                                        const std::atomic<bool>& stop) {
    const TraceTables& tb = in.tables;
    const int n = in.footprint_per_axis, width = in.camera.width(), height = in.camera.height();
    const int GC = tb.points * tb.columns;
    const std::size_t rays = static_cast<std::size_t>(n) * n;
    CameraQuadrature out;
    out.rays_per_axis = options.rays_given ? options.rays.front() : n;

    // 1. The step: all n x n rays at each coarser step against the smallest, radiance and alpha, on
    //    every stepCheckStride()-th pixel of every such row. The smallest step's rays first, kept per
    //    pixel (radiance, depths and source sums: at most 1/64 of the basis matrix's bytes), then the
    //    coarser steps from the coarsest, until the choice below can no longer change: it takes the
    //    coarsest step within each criterion, so once alpha's is found and the radiance rays' among
    //    the steps up to kRadianceStepOverDepthStep times it, the finer ones are not marched (frame
    //    12 upsampled 4x takes 4 times the smallest step: twice it, half the coarser steps' marching,
    //    is left out).
    const std::size_t S = options.step_scales.size();
    double step_error = 0.0;
    if (S > 0) {
        const int stride = stepCheckStride(width, height);
        const int columns_checked = (width - stride / 2 + stride - 1) / stride;
        const std::size_t sources = static_cast<std::size_t>(tb.points) * (1 + tb.columns - tb.bins);
        struct FinePixel {
            std::vector<float> radiance;  // the pixel's rows, GC floats (empty where no ray met density)
            std::vector<double> b, a, sums;  // its rays' depths (gatherRays) and source sums (addSourceSums)
        };
        std::vector<std::vector<FinePixel>> fine(height);
        std::vector<int> seen(height, 0);  // checked pixels a ray of which crossed density, per row
        std::vector<std::vector<double>> fine_sums(height);
        const auto checkedRow = [&](int py) { return py % stride == stride / 2; };
        tbb::parallel_for(0, height, [&](int py) {
            if (!checkedRow(py) || stop.load(std::memory_order_relaxed)) return;
            const std::unique_ptr<CameraMarch> march = cameraMarch(in, 1);
            fine[py].resize(columns_checked);
            fine_sums[py].assign(sources, 0.0);
            for (int c = 0; c < columns_checked; ++c) {
                FinePixel& pixel = fine[py][c];
                pixel.radiance.assign(GC, 0.0f);
                pixel.b.resize(rays);
                pixel.a.resize(rays * tb.n_alpha);
                march->beginPixel();
                gatherRays(*march, in.lbar_sum, width, stride / 2 + c * stride, py, n, pixel.radiance.data(),
                           tb.n_alpha, pixel.b.data(), pixel.a.data());
                if (!std::any_of(pixel.b.begin(), pixel.b.end(), [](double d) { return d > 0.0; })) {
                    pixel = FinePixel{};
                    continue;
                }
                ++seen[py];
                pixel.sums.assign(sources, 0.0);
                addSourceSums(pixel.radiance.data(), tb.points, tb.columns, tb.bins, pixel.sums.data());
                for (std::size_t k = 0; k < sources; ++k) fine_sums[py][k] += pixel.sums[k];
            }
        });
        // Too few pixels with density to judge the step by: the smallest (every step is measured, for
        // the report).
        const bool judged = std::accumulate(seen.begin(), seen.end(), 0) >= kMinStepCheckPixels;
        double fine_sum = 0.0;
        for (double v : rowTotals(fine_sums, sources)) fine_sum += std::fabs(v);
        // Step t against the smallest on every checked pixel with density.
        const auto measure = [&](std::size_t t) {
            std::vector<double> diff2(height, 0.0), value2(height, 0.0), alpha(height, 0.0);
            std::vector<std::vector<double>> change_sums(height);
            tbb::parallel_for(0, height, [&](int py) {
                if (!checkedRow(py) || stop.load(std::memory_order_relaxed)) return;
                const std::unique_ptr<CameraMarch> march = cameraMarch(in, options.step_scales[t]);
                std::vector<float> coarse(GC);
                std::vector<double> b1(rays), a1(rays * tb.n_alpha), pixel_coarse(sources);
                change_sums[py].assign(sources, 0.0);
                for (int c = 0; c < columns_checked; ++c) {
                    const FinePixel& pixel = fine[py][c];
                    if (pixel.radiance.empty()) continue;
                    coarse.assign(GC, 0.0f);
                    march->beginPixel();
                    gatherRays(*march, in.lbar_sum, width, stride / 2 + c * stride, py, n, coarse.data(),
                               tb.n_alpha, b1.data(), a1.data());
                    quadratureCheck(coarse.data(), pixel.radiance.data(), tb.points, tb.columns, tb.bins, diff2[py],
                                    value2[py]);
                    std::fill(pixel_coarse.begin(), pixel_coarse.end(), 0.0);
                    addSourceSums(coarse.data(), tb.points, tb.columns, tb.bins, pixel_coarse.data());
                    for (std::size_t k = 0; k < sources; ++k) change_sums[py][k] += pixel_coarse[k] - pixel.sums[k];
                    alpha[py] = std::max(alpha[py], worstAlphaChange(tb, n * n, pixel.b.data(), pixel.a.data(),
                                                                     b1.data(), a1.data()));
                }
            });
            double moved = 0.0;
            for (double v : rowTotals(change_sums, sources)) moved += std::fabs(v);
            return QuadratureCandidate{n, options.step_scales[t], relativeFrobeniusError(diff2, value2),
                                       fine_sum > 0.0 ? moved / fine_sum : 0.0,
                                       *std::max_element(alpha.begin(), alpha.end())};
        };
        const auto alphaWithin = [&](const QuadratureCandidate& c) { return c.alpha_error <= options.alpha_allowance; };
        const auto radianceWithin = [&](const QuadratureCandidate& c) {
            return c.radiance_error <= options.step_allowance && c.mean_change <= options.mean_change_allowance;
        };
        // The choice from the steps measured from `from` up (every coarser one measured): alpha's
        // step the coarsest within its allowance (else the smallest); the radiance rays' the coarsest
        // within theirs, up to kRadianceStepOverDepthStep times alpha's (camera_quadrature.h): finer
        // where radiance moves more than alpha, never coarser. Free of alpha's, the bundled sample's
        // frame 7 at 128x128 measured 0.085% at 4 times the step where alpha moved 0.019, and its
        // looks' error against the references rose from 0.10-0.24% to 0.26-0.49% with its radiance
        // rays there (alpha's at the smallest step). Settled once both are found: a finer step can
        // change neither.
        std::vector<std::optional<QuadratureCandidate>> measured(S);
        struct StepChoice {
            int depth_scale = 1, step_scale = 1;
            double step_error = 0.0;
            bool settled = false;
        };
        const auto choose = [&](std::size_t from) {
            StepChoice choice;
            bool depth_found = false;
            for (std::size_t u = from; u < S; ++u)
                if (alphaWithin(*measured[u])) {
                    choice.depth_scale = measured[u]->step_scale;
                    depth_found = true;
                }
            for (std::size_t u = from; u < S; ++u) {
                const QuadratureCandidate& c = *measured[u];
                if (c.step_scale <= kRadianceStepOverDepthStep * choice.depth_scale && radianceWithin(c)) {
                    choice.step_scale = c.step_scale;
                    choice.step_error = c.radiance_error;
                    choice.settled = depth_found;
                }
            }
            return choice;
        };
        std::size_t first = S;  // the finest step measured
        while (first > 0) {
            --first;
            measured[first] = measure(first);
            if (judged && !stop.load() && choose(first).settled) break;
        }
        for (const std::optional<QuadratureCandidate>& c : measured)
            if (c) out.candidates.push_back(*c);
        if (judged) {
            const StepChoice choice = choose(first);
            out.depth_step_scale = choice.depth_scale;
            out.step_scale = choice.step_scale;
            step_error = choice.step_error;
        }
    }

    // 2. The radiance rays at that step: all n x n against each m, on every kQuadratureCheckStride-th
    //    pixel of every kQuadratureCheckStride-th row, within what the step left of the allowance.
    const std::size_t M = options.rays.size();
    double rays_error = 0.0;
    if (M > 0) {
        std::vector<std::vector<double>> diff2(M, std::vector<double>(height, 0.0)),
            value2(M, std::vector<double>(height, 0.0));
        tbb::parallel_for(0, height, [&](int py) {
            if (py % kQuadratureCheckStride != kQuadratureCheckStride / 2 || stop.load(std::memory_order_relaxed))
                return;
            const std::unique_ptr<CameraMarch> ray_march = cameraMarch(in, out.step_scale);
            std::vector<float> fine(GC), coarse(GC);
            for (int px = kQuadratureCheckStride / 2; px < width; px += kQuadratureCheckStride) {
                fine.assign(GC, 0.0f);
                ray_march->beginPixel();
                gatherRadianceRays(*ray_march, in.lbar_sum, width, px, py, n, fine.data());
                for (std::size_t k = 0; k < M; ++k) {
                    coarse.assign(GC, 0.0f);
                    ray_march->beginPixel();
                    gatherRadianceRays(*ray_march, in.lbar_sum, width, px, py, options.rays[k], coarse.data());
                    quadratureCheck(coarse.data(), fine.data(), tb.points, tb.columns, tb.bins, diff2[k][py],
                                    value2[k][py]);
                }
            }
        });
        const double left = std::sqrt(std::max(0.0, options.allowance * options.allowance - step_error * step_error));
        for (std::size_t k = 0; k < M; ++k) {
            const double error = relativeFrobeniusError(diff2[k], value2[k]);
            out.candidates.push_back({options.rays[k], out.step_scale, error, 0.0, 0.0});
            if (options.rays_given || (out.rays_per_axis == n && error <= left)) {
                out.rays_per_axis = options.rays[k];
                rays_error = error;
            }
        }
    }
    // The two errors are of different kinds (where the rays sample the footprint, and the march along
    // each ray): they add in quadrature.
    out.radiance_error = std::hypot(step_error, rays_error);
    return out;
}

}  // namespace firelook::bake
