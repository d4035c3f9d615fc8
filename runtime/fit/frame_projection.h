// One frame's target projected once onto the frame's reconstruction basis U, so that the normal
// equations of the emission and lights at any extinction theta cost no pass over the pixels.
//
// For fixed theta the image is linear in the per-bin emission c_i and the lights' irradiance E_l
// (docs/model.md, "Basis images"), the same basis for R, G and B: image_c = U V_theta x_c, with
// V_theta the rank x (bins + lights) columns of S V^T blended at theta. The least-squares system on
// the target's weighted pixels is then
//   G = V^T K V,  b_c = V^T y_c,  with K = U^T W U (rank x rank) and y_c = U^T W t_c,
// both computed here once. Only alpha (and, over a background, the part of the target it hides)
// needs the pixels at each theta: one alpha pass of the runtime's reconstruction.
#pragma once

#include <array>
#include <vector>

#include "basis/bake_description.h"
#include "basis/resident_frame.h"
#include "fit/fit_target.h"

namespace firelook::fit {

// The normal equations summed over frames: n = bins + lights unknowns per channel (bins first).
struct NormalEquations {
    int n = 0;
    std::vector<double> gram;                // n x n, row-major
    std::array<std::vector<double>, 3> rhs;  // per channel, n
    std::array<double, 3> target_squares{};  // sum W t'^2 per channel, t' = what the emission must explain
    double alpha_squared_error = 0.0;        // sum W (alpha - alpha_target)^2 where alpha is matched

    explicit NormalEquations(int unknowns);
};

class FrameProjection {
  public:
    // Throws an InvalidArgument Error when the target's size differs from the description's image,
    // a weight is negative or not finite, or a target value is not finite (naming the pixel).
    FrameProjection(const basis::BakeDescription& description, const basis::ResidentFrame& frame,
                    const FrameTarget& target);

    // Adds this frame's G, b_c, target squares and alpha error at theta to `equations`.
    void accumulate(const ExtinctionParams& theta, NormalEquations& equations);

    // sum W t^2 over RGB and sum W alpha_t^2 (alpha 0 when not matched): the error's scales.
    double targetEnergy() const { return target_energy_; }
    double alphaEnergy() const { return alpha_energy_; }
    double totalWeight() const { return total_weight_; }
    bool matchesAlpha() const { return target_.match_alpha; }

  private:
    const basis::BakeDescription& description_;
    const basis::ResidentFrame& frame_;
    const FrameTarget& target_;
    int rank_ = 0;
    bool needs_alpha_ = false;       // alpha matched, or a background the alpha uncovers
    bool has_background_ = false;
    std::vector<int> pixels_;        // weighted pixels
    std::vector<float> weights_;     // their weights
    std::vector<float> u_rows_;      // their rows of U (rank each)
    std::vector<double> k_;          // K = U^T W U, rank x rank
    std::array<std::vector<double>, 3> y_;  // y_c = U^T W t_c
    std::vector<double> u_weight_;   // U^T W 1, for the background
    std::array<double, 3> target_squares_{};
    double target_energy_ = 0.0, alpha_energy_ = 0.0, total_weight_ = 0.0;
    // Scratch, reused between thetas.
    std::vector<float> zero_z_, rgba_, blended_;
    std::vector<double> kv_, hidden_, y_shifted_;
};

}  // namespace firelook::fit
