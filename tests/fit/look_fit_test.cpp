// fitLook (runtime/fit/look_fit.h) on a small baked package: looks rendered by the runtime are
// fitted back from their images alone.
#include "fit/look_fit.h"

#include <gtest/gtest.h>

#include <memory_resource>

#include "../support/error_code.h"
#include "basis/basis_package.h"
#include "basis/look_renderer.h"
#include "fit_test_package.h"

namespace firelook::fit {
namespace {

// The bar of issue 17: a target the package itself rendered is matched within 0.5% relative RMSE.
// The image is exactly in the model's span, so what remains is the search's step tolerance (1/256
// of a grid cell) and the clamp of negative radiance the fit's linear model does not see.
constexpr double kSelfConsistency = 0.005;

struct Fixture {
    basis::BasisReader package = basis::BasisReader::open(test::fitTestPackage());
    const basis::BakeDescription& d = package.description();
    basis::ResidentFrame frame = package.loadResidentFrame(6, std::pmr::get_default_resource());

    FrameTarget render(const Look& look) const {
        FrameTarget t;
        t.frame = 6;
        t.rgba.resize(static_cast<size_t>(d.pixelCount()) * 4);
        basis::renderLookImage(d, frame, look, t.rgba);
        return t;
    }
    FitResult fit(const FrameTarget& t, const FitOptions& options = {}) const {
        const basis::ResidentFrame* frames[] = {&frame};
        return fitLook(d, frames, std::span(&t, 1), options);
    }
};

TEST(LookFit, RecoversRandomLooksFromTheirImages) {
    const Fixture f;
    std::mt19937 rng(17);
    for (int i = 0; i < 4; ++i) {
        const Look truth = test::randomLook(rng, f.d.bins.count);
        const FitResult r = f.fit(f.render(truth));
        EXPECT_LT(r.relative_rmse, kSelfConsistency) << "look " << i;
        // Alpha is matched too: within 0.01 anywhere (the tolerance of the search in k_s, k_f and
        // T_c moves alpha by far less; the stored depths are exact for any k_s, k_f).
        EXPECT_LT(r.alpha_max_error, 0.01) << "look " << i;
        EXPECT_GT(r.evaluations, 12) << "every grid point, then the local search";
        for (float v : r.images[0]) ASSERT_TRUE(std::isfinite(v));
    }
}

TEST(LookFit, TheWrittenLookRendersToTheReportedError) {
    const Fixture f;
    std::mt19937 rng(5);
    const FrameTarget t = f.render(test::randomLook(rng, f.d.bins.count));
    const FitResult r = f.fit(t);
    const Look reread = parseLook(lookToJson(r.look), "round trip");
    const basis::ResidentFrame* frames[] = {&f.frame};
    const std::vector<FrameFitError> e = measureLook(f.d, frames, std::span(&t, 1), reread);
    // The look file holds floats exactly (look.h), and the emission refit gives back the fitted
    // coefficients to float rounding: the same error to 1e-4 of itself (plus 1e-9 absolute).
    EXPECT_NEAR(e[0].relative_rmse, r.relative_rmse, 1e-4 * r.relative_rmse + 1e-9);
    EXPECT_DOUBLE_EQ(reread.albedo, f.d.albedo);
}

TEST(LookFit, IsDeterministic) {
    const Fixture f;
    std::mt19937 rng(9);
    const FrameTarget t = f.render(test::randomLook(rng, f.d.bins.count));
    EXPECT_EQ(lookToJson(f.fit(t).look), lookToJson(f.fit(t).look));
}

TEST(LookFit, AMaskLeavesCorruptPixelsOut) {
    const Fixture f;
    std::mt19937 rng(21);
    FrameTarget t = f.render(test::randomLook(rng, f.d.bins.count));
    // The left half is overwritten by a bright flat colour that no look can make.
    t.weight.assign(static_cast<size_t>(f.d.pixelCount()), 1.0f);
    for (int y = 0; y < f.d.height; ++y)
        for (int x = 0; x < f.d.width / 2; ++x) {
            const size_t p = static_cast<size_t>(y) * f.d.width + x;
            for (int c = 0; c < 4; ++c) t.rgba[4 * p + c] = c == 3 ? 1.0f : 5.0f;
            t.weight[p] = 0.0f;
        }
    const FitResult masked = f.fit(t);
    EXPECT_LT(masked.relative_rmse, kSelfConsistency) << "measured on the kept half";
    t.weight.clear();
    const FitResult unmasked = f.fit(t);
    EXPECT_GT(unmasked.relative_rmse, 10.0 * kSelfConsistency) << "the corrupt half cannot be matched";
}

TEST(LookFit, MatchesAnOpaqueCompositeOverABackground) {
    const Fixture f;
    std::mt19937 rng(33);
    FrameTarget t = f.render(test::randomLook(rng, f.d.bins.count));
    t.match_alpha = false;
    t.background = Rgb(0.3f, 0.4f, 0.5f);
    for (size_t p = 0; p < static_cast<size_t>(f.d.pixelCount()); ++p) {
        float* px = t.rgba.data() + 4 * p;
        for (int c = 0; c < 3; ++c) px[c] += (1.0f - px[3]) * t.background[c];
        px[3] = 1.0f;
    }
    const FitResult r = f.fit(t);
    EXPECT_LT(r.relative_rmse, kSelfConsistency);
    EXPECT_EQ(r.alpha_max_error, 0.0) << "alpha is not matched over a background";
}

TEST(LookFit, HeldParametersStayAndAreChecked) {
    const Fixture f;
    std::mt19937 rng(41);
    Look truth = test::randomLook(rng, f.d.bins.count);
    truth.smoke_extinction = 5.0;
    FitOptions options;
    options.smoke_extinction = 5.0;
    const FitResult r = f.fit(f.render(truth), options);
    EXPECT_DOUBLE_EQ(r.look.smoke_extinction, 5.0);
    EXPECT_LT(r.relative_rmse, kSelfConsistency);

    options.smoke_extinction = 30.0;  // the axis is [2, 8]
    try {
        f.fit(f.render(truth), options);
        FAIL() << "no error for k_s outside its axis";
    } catch (const firelook::Error& e) {
        EXPECT_EQ(e.code(), firelook::ErrorCode::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("k_s"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("outside the baked range"), std::string::npos) << e.what();
    }
}

TEST(LookFit, SmoothnessMakesTheEmissionSmootherAtSomeCost) {
    const Fixture f;
    std::mt19937 rng(2);
    const FrameTarget t = f.render(test::randomLook(rng, f.d.bins.count));
    FitOptions smooth;
    smooth.smoothness = 10.0;
    const FitResult free = f.fit(t), smoothed = f.fit(t, smooth);
    const auto roughness = [](const std::vector<Rgb>& c) {
        double sum = 0.0;
        for (size_t i = 1; i + 1 < c.size(); ++i) {
            const Rgb d = c[i - 1] - 2.0f * c[i] + c[i + 1];
            sum += d.r * d.r + d.g * d.g + d.b * d.b;
        }
        return sum;
    };
    EXPECT_LT(roughness(smoothed.rbf_coefficients), roughness(free.rbf_coefficients));
    EXPECT_GE(smoothed.relative_rmse, free.relative_rmse * (1.0 - 1e-6));
}

TEST(LookFit, RefusesTargetsThatDoNotFit) {
    const Fixture f;
    FrameTarget t;
    t.frame = 6;
    t.rgba.assign(10 * 4, 0.0f);
    try {
        f.fit(t);
        FAIL() << "no error for a wrong-size target";
    } catch (const firelook::Error& e) {
        EXPECT_EQ(e.code(), firelook::ErrorCode::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("32x32"), std::string::npos) << e.what();
    }
    t.rgba.assign(static_cast<size_t>(f.d.pixelCount()) * 4, 0.0f);
    t.rgba[5] = std::nanf("");
    EXPECT_ERROR_CODE(firelook::ErrorCode::InvalidArgument, f.fit(t));
    t.rgba[5] = 0.0f;
    t.frame = 7;  // paired with frame 6
    EXPECT_ERROR_CODE(firelook::ErrorCode::InvalidArgument, f.fit(t));
}

TEST(LookFit, RefusesAMaskThatLeavesNoPixel) {
    const Fixture f;
    std::mt19937 rng(13);
    FrameTarget t = f.render(test::randomLook(rng, f.d.bins.count));
    t.weight.assign(static_cast<size_t>(f.d.pixelCount()), 0.0f);
    try {
        f.fit(t);
        FAIL() << "no error for a target with no weighted pixel";
    } catch (const firelook::Error& e) {
        EXPECT_EQ(e.code(), firelook::ErrorCode::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("no target pixel"), std::string::npos) << e.what();
    }
}

TEST(LookFit, ABlackTargetGivesNoEmissionAndNoNaN) {
    const Fixture f;
    FrameTarget t;
    t.frame = 6;
    t.rgba.assign(static_cast<size_t>(f.d.pixelCount()) * 4, 0.0f);
    const FitResult r = f.fit(t);
    for (const Rgb& e : std::get<EmissionBins>(r.look.emission).emissivity) EXPECT_EQ(e, Rgb(0.0f));
    EXPECT_TRUE(std::isfinite(r.relative_rmse));
    EXPECT_TRUE(std::isfinite(r.objective));
}

TEST(LookFit, OneLookForTwoFrames) {
    const Fixture f;
    const basis::ResidentFrame frame7 = f.package.loadResidentFrame(7, std::pmr::get_default_resource());
    std::mt19937 rng(8);
    const Look truth = test::randomLook(rng, f.d.bins.count);
    std::vector<FrameTarget> targets = {f.render(truth), FrameTarget{}};
    targets[1].frame = 7;
    targets[1].rgba.resize(static_cast<size_t>(f.d.pixelCount()) * 4);
    basis::renderLookImage(f.d, frame7, truth, targets[1].rgba);
    const basis::ResidentFrame* frames[] = {&f.frame, &frame7};
    const FitResult r = fitLook(f.d, frames, targets);
    ASSERT_EQ(r.frames.size(), 2u);
    for (const FrameFitError& e : r.frames) EXPECT_LT(e.relative_rmse, kSelfConsistency) << "frame " << e.frame;
}

}  // namespace
}  // namespace firelook::fit
