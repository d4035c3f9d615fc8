#include "fit/look_fit.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "basis/look_renderer.h"
#include "common/error.h"
#include "fit/frame_projection.h"
#include "fit/gram_nnls.h"

namespace firelook::fit {
namespace {

// An axis of theta in grid coordinates: u in [0, samples - 1] maps piecewise linearly onto the
// samples, so the basis images are linear in u within a cell and a step of 1 is one grid cell.
struct SearchAxis {
    const std::vector<double>* samples = nullptr;
    bool searched = false;
    double held_u = 0.0;

    double top() const { return static_cast<double>(samples->size() - 1); }
    double value(double u) const {
        const std::vector<double>& s = *samples;
        if (s.size() == 1) return s[0];
        const int i = std::clamp(static_cast<int>(std::floor(u)), 0, static_cast<int>(s.size()) - 2);
        const double f = std::clamp(u - i, 0.0, 1.0);
        return s[i] + f * (s[i + 1] - s[i]);
    }
    double coordinate(double v) const {
        const std::vector<double>& s = *samples;
        if (s.size() == 1) return 0.0;
        for (size_t i = 0; i + 1 < s.size(); ++i)
            if (v <= s[i + 1]) return static_cast<double>(i) + (v - s[i]) / (s[i + 1] - s[i]);
        return top();
    }
};

SearchAxis makeAxis(const std::vector<double>& samples, const std::optional<double>& held, const char* name) {
    SearchAxis axis;
    axis.samples = &samples;
    if (held) {
        if (!std::isfinite(*held) || *held < samples.front() - 1e-9 * std::abs(samples.front()) ||
            *held > samples.back() + 1e-9 * std::abs(samples.back()))
            throw Error(ErrorCode::InvalidArgument,
                        std::string(name) + " = " + std::to_string(*held) + " is outside the baked range [" +
                            std::to_string(samples.front()) + ", " + std::to_string(samples.back()) + "]");
        axis.held_u = axis.coordinate(std::clamp(*held, samples.front(), samples.back()));
    }
    axis.searched = !held && samples.size() > 1;
    return axis;
}

using Coordinates = std::array<double, 3>;

struct Evaluation {
    Coordinates u{};
    double objective = std::numeric_limits<double>::infinity();
    std::array<std::vector<double>, 3> x;  // per channel: bins, then lights
};

class Objective {
  public:
    Objective(const basis::BakeDescription& description, std::vector<FrameProjection>& projections,
              const FitOptions& options, const std::array<SearchAxis, 3>& axes)
        : description_(description), projections_(projections), options_(options), axes_(axes) {
        for (const FrameProjection& p : projections) {
            energy_ += p.targetEnergy();
            alpha_energy_ += p.alphaEnergy();
            if (p.matchesAlpha()) alpha_weight_sum_ += p.totalWeight();
        }
        // Relative to the target's alpha; a target transparent everywhere, per unit weight.
        alpha_scale_ = alpha_energy_ > 0.0 ? alpha_energy_ : std::max(alpha_weight_sum_, 1.0);
    }

    ExtinctionParams theta(const Coordinates& u) const {
        return {axes_[0].value(u[0]), axes_[1].value(u[1]), axes_[2].value(u[2])};
    }

    Evaluation evaluate(const Coordinates& u) {
        ++count_;
        const int n = description_.columnsPerPoint();
        NormalEquations eq(n);
        const ExtinctionParams t = theta(u);
        for (FrameProjection& p : projections_) p.accumulate(t, eq);

        std::vector<double> solve_gram = eq.gram;
        addSmoothness(solve_gram, n);
        Evaluation e;
        e.u = u;
        double squared_error = 0.0;
        for (int c = 0; c < 3; ++c) {
            e.x[c] = solveGramNnls(solve_gram, eq.rhs[c], n);
            // |A x - t'|^2 = x^T G x - 2 b^T x + t'^T t' (G without the smoothness term).
            double quadratic = 0.0, linear = 0.0;
            for (int i = 0; i < n; ++i) {
                double row = 0.0;
                for (int j = 0; j < n; ++j) row += eq.gram[i * n + j] * e.x[c][j];
                quadratic += e.x[c][i] * row;
                linear += eq.rhs[c][i] * e.x[c][i];
            }
            squared_error += std::max(quadratic - 2.0 * linear + eq.target_squares[c], 0.0);
        }
        // A black target is matched absolutely (its energy would divide by zero).
        e.objective = squared_error / (energy_ > 0.0 ? energy_ : 1.0);
        e.objective += options_.alpha_weight * eq.alpha_squared_error / alpha_scale_;
        if (!std::isfinite(e.objective)) e.objective = std::numeric_limits<double>::max();
        return e;
    }

    int count() const { return count_; }

  private:
    // + lambda s D^T D on the bins' block, D the second differences, s the block's mean diagonal.
    void addSmoothness(std::vector<double>& gram, int n) const {
        const int bins = description_.bins.count;
        if (!(options_.smoothness > 0.0) || bins < 3) return;
        double scale = 0.0;
        for (int i = 0; i < bins; ++i) scale += gram[i * n + i];
        scale = options_.smoothness * scale / bins;
        for (int i = 1; i + 1 < bins; ++i) {
            const int idx[3] = {i - 1, i, i + 1};
            const double d[3] = {1.0, -2.0, 1.0};
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b) gram[idx[a] * n + idx[b]] += scale * d[a] * d[b];
        }
    }

    const basis::BakeDescription& description_;
    std::vector<FrameProjection>& projections_;
    const FitOptions& options_;
    const std::array<SearchAxis, 3>& axes_;
    double energy_ = 0.0, alpha_energy_ = 0.0, alpha_weight_sum_ = 0.0, alpha_scale_ = 1.0;
    int count_ = 0;
};

// Every combination of the searched axes' grid points (the held ones at their value).
std::vector<Coordinates> gridPoints(const std::array<SearchAxis, 3>& axes) {
    std::vector<Coordinates> points{{axes[0].held_u, axes[1].held_u, axes[2].held_u}};
    for (int d = 0; d < 3; ++d) {
        if (!axes[d].searched) continue;
        std::vector<Coordinates> next;
        for (const Coordinates& p : points)
            for (size_t i = 0; i < axes[d].samples->size(); ++i) {
                Coordinates q = p;
                q[d] = static_cast<double>(i);
                next.push_back(q);
            }
        points = std::move(next);
    }
    return points;
}

// Compass search: try +-step along each searched axis, move to the first improvement, halve the
// step when none improves; stops below the tolerance. report(level fraction) after each level.
Evaluation compassSearch(Objective& objective, const std::array<SearchAxis, 3>& axes, Evaluation start,
                         double tolerance, const std::function<void(double)>& report) {
    double step = 0.5;
    const double levels = std::max(1.0, std::log2(0.5 / tolerance) + 1.0);
    int level = 0;
    Evaluation best = std::move(start);
    while (step >= tolerance) {
        bool moved = false;
        for (int d = 0; d < 3 && !moved; ++d) {
            if (!axes[d].searched) continue;
            for (double sign : {1.0, -1.0}) {
                Coordinates u = best.u;
                u[d] = std::clamp(u[d] + sign * step, 0.0, axes[d].top());
                if (u[d] == best.u[d]) continue;
                Evaluation e = objective.evaluate(u);
                if (e.objective < best.objective) {
                    best = std::move(e);
                    moved = true;
                    break;
                }
            }
        }
        if (!moved) {
            step *= 0.5;
            ++level;
            report(std::min(1.0, level / levels));
        }
    }
    return best;
}

std::vector<Rgb> channelsToRgb(const std::array<std::vector<double>, 3>& x, int first, int count) {
    std::vector<Rgb> out(count);
    for (int i = 0; i < count; ++i)
        for (int c = 0; c < 3; ++c) out[i][c] = static_cast<float>(x[c][first + i]);
    return out;
}

}  // namespace

std::vector<FrameFitError> measureLook(const basis::BakeDescription& description,
                                       std::span<const basis::ResidentFrame* const> frames,
                                       std::span<const FrameTarget> targets, const Look& look,
                                       std::vector<std::vector<float>>* images_out) {
    if (frames.size() != targets.size())
        throw Error(ErrorCode::InvalidArgument, "measureLook: one frame per target");
    std::vector<FrameFitError> errors;
    if (images_out) images_out->clear();
    const size_t pixels = static_cast<size_t>(description.pixelCount());
    for (size_t f = 0; f < frames.size(); ++f) {
        const FrameTarget& target = targets[f];
        if (target.rgba.size() != pixels * 4 || (!target.weight.empty() && target.weight.size() != pixels))
            throw Error(ErrorCode::InvalidArgument, "frame " + std::to_string(target.frame) +
                                                        " target: size differs from the package's images");
        std::vector<float> image(pixels * 4);
        basis::renderLookImage(description, *frames[f], look, image);
        FrameFitError e;
        e.frame = target.frame;
        for (size_t p = 0; p < pixels; ++p) {
            const double w = target.weight.empty() ? 1.0 : target.weight[p];
            if (w == 0.0) continue;
            const float* i = image.data() + 4 * p;
            const float* t = target.rgba.data() + 4 * p;
            const double uncovered = target.match_alpha ? 0.0 : 1.0 - i[3];
            for (int c = 0; c < 3; ++c) {
                const double d = i[c] + uncovered * target.background[c] - t[c];
                e.squared_error += w * d * d;
                e.target_energy += w * double(t[c]) * t[c];
            }
            e.total_weight += w;
            if (target.match_alpha) {
                const double d = double(i[3]) - t[3];
                e.alpha_squared_error += w * d * d;
                e.alpha_max_error = std::max(e.alpha_max_error, std::abs(d));
            }
        }
        const FrameFitError pooled = pooledError(std::span(&e, 1));
        e.relative_rmse = pooled.relative_rmse;
        e.alpha_rmse = pooled.alpha_rmse;
        errors.push_back(e);
        if (images_out) images_out->push_back(std::move(image));
    }
    return errors;
}

FrameFitError pooledError(std::span<const FrameFitError> frames) {
    FrameFitError p;
    p.frame = -1;
    for (const FrameFitError& e : frames) {
        p.squared_error += e.squared_error;
        p.target_energy += e.target_energy;
        p.alpha_squared_error += e.alpha_squared_error;
        p.total_weight += e.total_weight;
        p.alpha_max_error = std::max(p.alpha_max_error, e.alpha_max_error);
    }
    // A black target: any light at all is an infinite relative error, none is none.
    p.relative_rmse = p.target_energy > 0.0 ? std::sqrt(p.squared_error / p.target_energy)
                      : p.squared_error > 0.0 ? std::numeric_limits<double>::infinity()
                                              : 0.0;
    p.alpha_rmse = p.total_weight > 0.0 ? std::sqrt(p.alpha_squared_error / p.total_weight) : 0.0;
    return p;
}

FitResult fitLook(const basis::BakeDescription& description, std::span<const basis::ResidentFrame* const> frames,
                  std::span<const FrameTarget> targets, const FitOptions& options,
                  const std::function<void(double)>& progress) {
    if (frames.empty() || frames.size() != targets.size())
        throw Error(ErrorCode::InvalidArgument, "fitLook: one resident frame per target, at least one");
    if (!(options.smoothness >= 0.0) || !std::isfinite(options.smoothness) || !(options.alpha_weight >= 0.0) ||
        !std::isfinite(options.alpha_weight) || options.starts < 1 || !(options.step_tolerance > 0.0))
        throw Error(ErrorCode::InvalidArgument,
                    "fitLook: smoothness and alpha_weight must be finite and >= 0, starts >= 1, "
                    "step_tolerance > 0");
    const auto report = [&](double fraction) {
        if (progress) progress(std::clamp(fraction, 0.0, 1.0));
    };
    basis::validateAxes(description.axes);
    const std::array<SearchAxis, 3> axes = {
        makeAxis(description.axes.temperature_threshold, options.temperature_threshold, "T_c"),
        makeAxis(description.axes.smoke_extinction, options.smoke_extinction, "k_s"),
        makeAxis(description.axes.flame_extinction, options.flame_extinction, "k_f")};

    // Projecting the targets is the one pass over all pixels: 5% of the progress.
    std::vector<FrameProjection> projections;
    projections.reserve(frames.size());
    for (size_t f = 0; f < frames.size(); ++f) {
        if (frames[f]->frame != targets[f].frame)
            throw Error(ErrorCode::InvalidArgument,
                        "fitLook: target for frame " + std::to_string(targets[f].frame) +
                            " paired with resident frame " + std::to_string(frames[f]->frame));
        projections.emplace_back(description, *frames[f], targets[f]);
        report(0.05 * (f + 1) / frames.size());
    }
    // With no pixel weighted every look fits equally well (a 0% error on nothing): refuse it.
    double total_weight = 0.0;
    for (const FrameProjection& p : projections) total_weight += p.totalWeight();
    if (!(total_weight > 0.0))
        throw Error(ErrorCode::InvalidArgument,
                    "fitLook: no target pixel has a weight above 0 (an empty mask?): nothing to fit");
    Objective objective(description, projections, options, axes);

    // Coarse: every grid point of the searched axes (25% of the progress).
    const std::vector<Coordinates> grid = gridPoints(axes);
    std::vector<Evaluation> coarse;
    coarse.reserve(grid.size());
    for (size_t i = 0; i < grid.size(); ++i) {
        coarse.push_back(objective.evaluate(grid[i]));
        report(0.05 + 0.25 * (i + 1) / grid.size());
    }
    // Stable: equal objectives keep the grid's order, so the result does not depend on the sort.
    std::stable_sort(coarse.begin(), coarse.end(),
                     [](const Evaluation& a, const Evaluation& b) { return a.objective < b.objective; });

    // Fine: a compass search from each of the best few.
    const int starts = std::min<int>(options.starts, static_cast<int>(coarse.size()));
    Evaluation best;
    for (int s = 0; s < starts; ++s) {
        Evaluation e = compassSearch(objective, axes, coarse[s], options.step_tolerance, [&](double level) {
            report(0.3 + 0.65 * (s + level) / starts);
        });
        if (e.objective < best.objective) best = std::move(e);
    }

    FitResult result;
    result.objective = best.objective;
    result.evaluations = objective.count();
    const int bins = description.bins.count;
    const int lights = static_cast<int>(description.light_directions.size());
    result.rbf_coefficients = channelsToRgb(best.x, 0, bins);

    // The look file stores the emissivity at the bin centres, e_j = sum_i c_i phi_i(T_j); the
    // look's emission fit (fitEmissionCoefficients) inverts exactly this system, and its solution
    // c >= 0 is the fitted one.
    const EmissionBasis basis{description.bins, description.rbf_width, description.emission_clamp_to_centres};
    std::vector<Rgb> emissivity(bins, Rgb(0.0f));
    for (int j = 0; j < bins; ++j) {
        glm::dvec3 sum(0.0);
        for (int i = 0; i < bins; ++i)
            sum += glm::dvec3(result.rbf_coefficients[i]) * basis.evaluate(i, description.bins.center(j));
        emissivity[j] = Rgb(sum);
    }
    const ExtinctionParams theta = objective.theta(best.u);
    Look& look = result.look;
    look.temperature_threshold = theta.temperature_threshold;
    look.smoke_extinction = theta.smoke_extinction;
    look.flame_extinction = theta.flame_extinction;
    look.albedo = description.albedo;
    look.emission = EmissionBins{emissivity};
    look.light_irradiance = channelsToRgb(best.x, bins, lights);
    look.source_name = "fitted look";

    result.frames = measureLook(description, frames, targets, look, &result.images);
    const FrameFitError pooled = pooledError(result.frames);
    result.relative_rmse = pooled.relative_rmse;
    result.alpha_rmse = pooled.alpha_rmse;
    result.alpha_max_error = pooled.alpha_max_error;
    report(1.0);
    return result;
}

}  // namespace firelook::fit
