#include "fit/frame_projection.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "basis/parameter_grid.h"
#include "basis/recombine.h"
#include "common/error.h"

namespace firelook::fit {

NormalEquations::NormalEquations(int unknowns)
    : n(unknowns), gram(static_cast<size_t>(unknowns) * unknowns, 0.0) {
    for (auto& r : rhs) r.assign(unknowns, 0.0);
}

FrameProjection::FrameProjection(const basis::BakeDescription& description, const basis::ResidentFrame& frame,
                                 const FrameTarget& target)
    : description_(description), frame_(frame), target_(target), rank_(frame.rank) {
    const int pixels = description.pixelCount();
    const std::string where = "frame " + std::to_string(target.frame) + " target: ";
    if (frame.pixels != pixels)
        throw Error(ErrorCode::InvalidArgument, where + "the frame's pixel count differs from the package's");
    if (target.rgba.size() != static_cast<size_t>(pixels) * 4)
        throw Error(ErrorCode::InvalidArgument,
                    where + std::to_string(target.rgba.size() / 4) + " pixels, the package's images have " +
                        std::to_string(pixels) + " (" + std::to_string(description.width) + "x" +
                        std::to_string(description.height) + ")");
    if (!target.weight.empty() && target.weight.size() != static_cast<size_t>(pixels))
        throw Error(ErrorCode::InvalidArgument,
                    where + "the mask has " + std::to_string(target.weight.size()) +
                        " pixels, the package's images have " + std::to_string(pixels));
    for (int c = 0; c < 3; ++c)
        if (!std::isfinite(target.background[c]) || target.background[c] < 0.0f)
            throw Error(ErrorCode::InvalidArgument, where + "the background must be finite and >= 0");
    has_background_ = !target.match_alpha && (target.background.r > 0.0f || target.background.g > 0.0f ||
                                              target.background.b > 0.0f);
    needs_alpha_ = target.match_alpha || has_background_;

    const auto pixelName = [&](int p) {
        return "pixel (" + std::to_string(p % description.width) + ", " + std::to_string(p / description.width) + ")";
    };
    const size_t stride = static_cast<size_t>(frame.rank_stride);
    for (int p = 0; p < pixels; ++p) {
        const float w = target.weight.empty() ? 1.0f : target.weight[p];
        if (!std::isfinite(w) || w < 0.0f)
            throw Error(ErrorCode::InvalidArgument,
                        where + "mask weight of " + pixelName(p) + " is not a finite value >= 0");
        for (int c = 0; c < 4; ++c)
            if (!std::isfinite(target.rgba[4 * static_cast<size_t>(p) + c]))
                throw Error(ErrorCode::InvalidArgument, where + pixelName(p) + " is not finite");
        if (w == 0.0f) continue;
        pixels_.push_back(p);
        weights_.push_back(w);
        for (int k = 0; k < rank_; ++k)
            u_rows_.push_back(static_cast<float>(frame.w[p * stride + k]) * frame.u_scale[k]);
    }

    // K = U^T W U and y_c = U^T W t_c in double: the error is read off x^T G x - 2 b^T x + t^T t,
    // a difference of terms of the target's size, so float sums (relative 1e-4 over 65536 pixels)
    // would put a floor of about 1% under the relative RMSE it can resolve.
    const size_t r = static_cast<size_t>(rank_);
    k_.assign(r * r, 0.0);
    for (auto& y : y_) y.assign(r, 0.0);
    u_weight_.assign(r, 0.0);
    std::vector<double> row(r);
    for (size_t i = 0; i < pixels_.size(); ++i) {
        const double w = weights_[i];
        const float* u = u_rows_.data() + i * r;
        const float* t = target.rgba.data() + 4 * static_cast<size_t>(pixels_[i]);
        for (size_t k = 0; k < r; ++k) row[k] = u[k];
        for (size_t a = 0; a < r; ++a) {
            const double wa = w * row[a];
            double* k_row = k_.data() + a * r;
            for (size_t b = a; b < r; ++b) k_row[b] += wa * row[b];
            for (int c = 0; c < 3; ++c) y_[c][a] += wa * t[c];
            u_weight_[a] += wa;
        }
        for (int c = 0; c < 3; ++c) target_squares_[c] += w * double(t[c]) * t[c];
        total_weight_ += w;
        if (target.match_alpha) alpha_energy_ += w * double(t[3]) * t[3];
    }
    for (size_t a = 0; a < r; ++a)
        for (size_t b = 0; b < a; ++b) k_[a * r + b] = k_[b * r + a];
    target_energy_ = target_squares_[0] + target_squares_[1] + target_squares_[2];

    zero_z_.assign(r * 3, 0.0f);
    if (needs_alpha_) rgba_.assign(static_cast<size_t>(pixels) * 4, 0.0f);
    y_shifted_.assign(r, 0.0);
}

void FrameProjection::accumulate(const ExtinctionParams& theta, NormalEquations& eq) {
    const int n = eq.n;
    const size_t r = static_cast<size_t>(rank_);
    if (n != description_.columnsPerPoint())
        throw Error(ErrorCode::InvalidArgument, "normal equations sized for another package");

    // Alpha at theta: the runtime's reconstruction with z = 0 (colour 0, alpha exact).
    if (needs_alpha_) basis::reconstructImage(description_, frame_, zero_z_, theta, rgba_);

    // V: the columns of S V^T blended at theta (what the coefficient kernel weights).
    const basis::GridWeights grid = basis::interpolationWeights(description_.axes, theta);
    blended_.assign(r * n, 0.0f);
    for (int g = 0; g < grid.count; ++g) {
        const float gw = grid.weight[g];
        const float* columns = frame_.svt.data() + static_cast<size_t>(grid.point[g]) * n * r;
        for (size_t i = 0; i < r * n; ++i) blended_[i] += gw * columns[i];
    }
    // KV = K V (double), G += V^T K V.
    kv_.assign(r * n, 0.0);
    for (int j = 0; j < n; ++j) {
        const float* v = blended_.data() + j * r;
        double* out = kv_.data() + j * r;
        for (size_t a = 0; a < r; ++a) {
            const double* k_row = k_.data() + a * r;
            double sum = 0.0;
            for (size_t b = 0; b < r; ++b) sum += k_row[b] * v[b];
            out[a] = sum;
        }
    }
    for (int i = 0; i < n; ++i) {
        const float* v = blended_.data() + i * r;
        for (int j = i; j < n; ++j) {
            const double* w = kv_.data() + j * r;
            double sum = 0.0;
            for (size_t a = 0; a < r; ++a) sum += v[a] * w[a];
            eq.gram[i * n + j] += sum;
            if (j != i) eq.gram[j * n + i] += sum;
        }
    }

    // Over a background the emission explains t' = t - (1 - alpha) bg: y'_c = y_c - bg_c U^T W (1 - alpha).
    if (has_background_) {
        hidden_ = u_weight_;  // U^T W (1 - alpha)
        for (size_t i = 0; i < pixels_.size(); ++i) {
            const double wa = double(weights_[i]) * rgba_[4 * static_cast<size_t>(pixels_[i]) + 3];
            const float* u = u_rows_.data() + i * r;
            for (size_t a = 0; a < r; ++a) hidden_[a] -= wa * u[a];
        }
    }
    for (int c = 0; c < 3; ++c) {
        const float bg = target_.background[c];
        for (size_t a = 0; a < r; ++a) y_shifted_[a] = y_[c][a] - (has_background_ ? bg * hidden_[a] : 0.0);
        for (int j = 0; j < n; ++j) {
            const float* v = blended_.data() + j * r;
            double sum = 0.0;
            for (size_t a = 0; a < r; ++a) sum += v[a] * y_shifted_[a];
            eq.rhs[c][j] += sum;
        }
    }
    if (has_background_) {
        for (size_t i = 0; i < pixels_.size(); ++i) {
            const float* t = target_.rgba.data() + 4 * static_cast<size_t>(pixels_[i]);
            const double uncovered = 1.0 - rgba_[4 * static_cast<size_t>(pixels_[i]) + 3];
            for (int c = 0; c < 3; ++c) {
                const double shifted = t[c] - uncovered * target_.background[c];
                eq.target_squares[c] += weights_[i] * shifted * shifted;
            }
        }
    } else {
        for (int c = 0; c < 3; ++c) eq.target_squares[c] += target_squares_[c];
    }
    if (target_.match_alpha) {
        double sum = 0.0;
        for (size_t i = 0; i < pixels_.size(); ++i) {
            const size_t p = 4 * static_cast<size_t>(pixels_[i]);
            const double e = double(rgba_[p + 3]) - target_.rgba[p + 3];
            sum += weights_[i] * e * e;
        }
        eq.alpha_squared_error += sum;
    }
}

}  // namespace firelook::fit
