// Inverse design (issue 17): the look inside a package's baked ranges whose recombined image best
// matches target images of some of its frames.
//
// The objective is relative: sum W |rgb - t|^2 / sum W |t|^2 over linear RGB (the composite over
// the background where alpha is not matched), plus alpha_weight * sum W (alpha - alpha_t)^2 /
// sum W alpha_t^2 where it is. For a fixed theta = (T_c, k_s, k_f) the colour is linear in the
// per-bin emission c_i and the light irradiances E_l, so their best non-negative values are an
// exact small least-squares problem per channel (frame_projection.h, gram_nnls.h); theta itself is
// searched inside the baked axes: every grid point of the searched axes first, then a compass
// search (step halving, in units of grid cells) from the best few, clamped to the axes' ends. The
// search is deterministic: the same inputs give the same look, bit for bit.
//
// Not unique in general: where k_s and k_f are close, T_c changes nothing; where no voxel of a
// bin's temperature is seen, that bin's emission is 0 (any value fits as well); over a black
// background without alpha, extinction and emission trade against each other.
#pragma once

#include <functional>
#include <optional>
#include <span>
#include <vector>

#include "basis/bake_description.h"
#include "basis/resident_frame.h"
#include "fit/fit_target.h"
#include "look/look.h"

namespace firelook::fit {

struct FitOptions {
    // Held at this value (which must lie inside the baked axis) instead of searched. An axis baked
    // at one sample is held at it anyway.
    std::optional<double> temperature_threshold, smoke_extinction, flame_extinction;
    // Weight of the emission's second differences across bins (sum_i |c_{i-1} - 2 c_i + c_{i+1}|^2),
    // relative to the mean diagonal of the bins' normal equations: 0 fits each bin freely; about 1
    // makes the emission smooth in temperature at some cost in error.
    double smoothness = 0.0;
    double alpha_weight = 1.0;  // of the alpha term against the colour term (both relative)
    int starts = 3;              // grid points the local search starts from
    double step_tolerance = 1.0 / 256.0;  // the local search stops below this step, in grid cells
};

// The fitted look against one frame's target, the look rendered as `firelook render` draws it.
struct FrameFitError {
    int frame = 0;
    double relative_rmse = 0.0;    // sqrt(sum W |rgb - t|^2 / sum W |t|^2), linear RGB
    double alpha_rmse = 0.0;       // sqrt(sum W (alpha - alpha_t)^2 / sum W); 0 when alpha is not matched
    double alpha_max_error = 0.0;  // over pixels with W > 0; 0 when alpha is not matched
    // The sums behind them, for pooling frames: sum W |rgb - t|^2, sum W |t|^2, sum W (alpha -
    // alpha_t)^2, sum W.
    double squared_error = 0.0, target_energy = 0.0, alpha_squared_error = 0.0, total_weight = 0.0;
};

struct FitResult {
    Look look;  // theta, the emissivity at each bin centre ("bins"), the lights, the baked albedo
    std::vector<Rgb> rbf_coefficients;  // c_i >= 0 as fitted (look's emission refits to these)
    double relative_rmse = 0.0;         // over every frame together, as FrameFitError
    double alpha_rmse = 0.0, alpha_max_error = 0.0;
    std::vector<FrameFitError> frames;
    std::vector<std::vector<float>> images;  // the look recombined per frame: pixels x 4, premultiplied
    double objective = 0.0;                  // of the linear model at the result (see above)
    int evaluations = 0;                     // thetas evaluated
};

// frames[i] is the resident form of targets[i].frame (BasisReader::loadResidentFrame). `progress`,
// if given, is called with the fraction done at least every few milliseconds of work; an exception
// it throws (an interrupt) propagates with nothing left behind. Throws an InvalidArgument Error for
// targets that do not fit the package (size, counts, a non-finite value, a fixed value outside
// its axis, no frame, every pixel's weight 0), naming the frame and the problem.
FitResult fitLook(const basis::BakeDescription& description, std::span<const basis::ResidentFrame* const> frames,
                  std::span<const FrameTarget> targets, const FitOptions& options = {},
                  const std::function<void(double)>& progress = {});

// The errors fitLook reports, for any look: renders it on each frame (basis::renderLookImage) and
// compares with the targets. `images_out`, if given, receives the rendered images.
std::vector<FrameFitError> measureLook(const basis::BakeDescription& description,
                                       std::span<const basis::ResidentFrame* const> frames,
                                       std::span<const FrameTarget> targets, const Look& look,
                                       std::vector<std::vector<float>>* images_out = nullptr);

// The frames' errors pooled: relative RMSE and alpha RMSE over all their pixels, the largest alpha error.
// frame is -1 in the result.
FrameFitError pooledError(std::span<const FrameFitError> frames);

}  // namespace firelook::fit
