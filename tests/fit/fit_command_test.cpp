// `firelook fit` end to end (docs/cli.md, "firelook fit"): the built executable on the small package.
#include <gtest/gtest.h>

#include <array>
#include <fstream>

#include "../support/command.h"
#include "fit_test_package.h"
#include "image/image_io.h"

namespace firelook::fit {
namespace {

using firelook::testing::CommandResult;
using firelook::testing::lines;
using firelook::testing::runFirelook;
using firelook::testing::TempDir;

// The package rendered with a known look: the target a fit must recover.
void writeLookAndTarget(const TempDir& dir, const std::string& image, int frame = 6) {
    std::ofstream(dir / "truth.json") << R"({"format": "firelook-look", "version": 1,
        "temperature_threshold": 1.3, "smoke_extinction": 5.0, "flame_extinction": 1.2, "albedo": 0.7,
        "emission": {"stops": [[0.0, 0,0,0], [1.0, 3,0.8,0.1], [2.5, 14,7,2]]}, "light_irradiance": [[0.8, 0.9, 1.0]]})";
    const CommandResult r = runFirelook(dir, "render '" + test::fitTestPackage().string() + "' --frame " +
                                                 std::to_string(frame) + " --look truth.json -o " + image);
    ASSERT_EQ(r.exit_code, 0) << r.err;
}

double compare(const TempDir& dir, const std::string& a, const std::string& b) {
    const CommandResult r = runFirelook(dir, "compare " + a + " " + b + " --json");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    const size_t at = r.out.find("\"relative_rmse\": ");
    return at == std::string::npos ? 1.0 : std::stod(r.out.substr(at + 17));
}

TEST(FitCommand, FitsAnExrTargetAndTheLookRendersIt) {
    TempDir dir;
    writeLookAndTarget(dir, "target.exr");
    const std::string pkg = "'" + test::fitTestPackage().string() + "'";
    CommandResult r = runFirelook(dir, "fit " + pkg + " --frame 6 --target target.exr -o fitted.json --image fit.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("relative RMSE"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("T_c"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("light 0 irradiance"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(" s in all"), std::string::npos) << r.out;
    r = runFirelook(dir, "render " + pkg + " --frame 6 --look fitted.json -o again.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    // The self-consistency bar (0.5%), and the look file renders what --image wrote (EXR halves
    // both: 2^-11 relative per value).
    EXPECT_LT(compare(dir, "again.exr", "target.exr"), 0.005);
    EXPECT_LT(compare(dir, "again.exr", "fit.exr"), 1e-3);
    EXPECT_EQ(dir.entries(), (std::vector<std::string>{"again.exr", "fit.exr", "fitted.json", "target.exr", "truth.json"}));
}

TEST(FitCommand, FitsAPngTargetThroughTheDisplayTransformWithExposure) {
    TempDir dir;
    writeLookAndTarget(dir, "target.exr");
    const std::string pkg = "'" + test::fitTestPackage().string() + "'";
    // At -4 stops no pixel clips (the look's brightest emission is 14): a clipped pixel is left out
    // of the fit, and at -2 the whole core is, which leaves the hottest bins free (7% off).
    CommandResult r = runFirelook(dir, "render " + pkg + " --frame 6 --look truth.json --exposure -4 -o target.png");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = runFirelook(dir, "fit " + pkg + " --frame 6 --target target.png --exposure -4 -o fitted.json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.out.find("clipped"), std::string::npos) << r.out;
    r = runFirelook(dir, "render " + pkg + " --frame 6 --look fitted.json -o again.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    // 8-bit sRGB quantises each value by up to half a code (about 0.2% to 2% of it, more in the
    // dark), and premultiplying by an 8-bit alpha adds as much: 3% in linear RGB is well above
    // what an exact fit of the quantised target leaves and far below a wrong exposure (x4 here).
    EXPECT_LT(compare(dir, "again.exr", "target.exr"), 0.03);
}

TEST(FitCommand, SaysHowManyClippedPixelsItLeftOut) {
    TempDir dir;
    writeLookAndTarget(dir, "target.exr");
    const std::string pkg = "'" + test::fitTestPackage().string() + "'";
    CommandResult r = runFirelook(dir, "render " + pkg + " --frame 6 --look truth.json --exposure 1 -o target.png");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = runFirelook(dir, "fit " + pkg + " --frame 6 --target target.png --exposure 1 -o fitted.json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find(" clipped target pixels left out"), std::string::npos) << r.out;
}

TEST(FitCommand, APngOverABackgroundWithExposureIsDrawnBackTheSame) {
    TempDir dir;
    writeLookAndTarget(dir, "target.exr");
    // The target as an opaque PNG over a background, exposed by -1 stop; the background is
    // composited after the exposure (image_io.h), so it is given to fit as drawn.
    image::WriteOptions options;
    options.png_exposure_stops = -1.0;
    options.png_background = std::array<float, 3>{0.2f, 0.3f, 0.4f};
    image::writeImage(dir / "target.png", image::readImage(dir / "target.exr"), options);
    const std::string pkg = "'" + test::fitTestPackage().string() + "'";
    const CommandResult r = runFirelook(dir, "fit " + pkg + " --frame 6 --target target.png --exposure -1 "
                                             "--background 0.2,0.3,0.4 -o fitted.json --image fit.png");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    // The fit's picture is drawn over the same background at the same exposure: within the 8-bit
    // quantisation of both PNGs (the 3% of the PNG test above); a background dimmed by the
    // exposure a second time would be off by half of it over most of the picture.
    EXPECT_LT(compare(dir, "fit.png", "target.png"), 0.03);
}

TEST(FitCommand, OneLookForSeveralFramesWithAPattern) {
    TempDir dir;
    writeLookAndTarget(dir, "t_06.exr", 6);
    writeLookAndTarget(dir, "t_07.exr", 7);
    const std::string pkg = "'" + test::fitTestPackage().string() + "'";
    CommandResult r = runFirelook(dir, "fit " + pkg + " --frames 6-7 --target t_##.exr -o fitted.json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("frame 7: relative RMSE"), std::string::npos) << r.out;
    r = runFirelook(dir, "fit " + pkg + " --frames 6-7 --target t_06.exr -o other.json");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("'#'"), std::string::npos) << r.err;
}

TEST(FitCommand, BadInputIsOneLineNamingTheFileAndWritesNothing) {
    TempDir dir;
    const std::string pkg = "'" + test::fitTestPackage().string() + "'";
    image::writeImage(dir / "small.exr", image::ImageRGBA(8, 8));
    image::writeImage(dir / "black.exr", image::ImageRGBA(32, 32));
    image::writeImage(dir / "zero.png", image::ImageRGBA(32, 32));
    struct Case {
        std::string args, names;
    } cases[] = {
        {"--frame 6 --target small.exr", "small.exr: 8x8, but the package's images are 32x32"},
        {"--frame 6 --target missing.exr", "missing.exr"},
        {"--frame 9 --target small.exr", "has no frame 9"},
        {"--frame 6 --target small.exr --fix k_q=1", "unknown parameter 'k_q'"},
        {"--frame 6 --target black.exr --mask missing_mask.png", "missing_mask.png"},
        {"--frame 6 --target black.exr --mask zero.png", "zero.png: leaves no pixel of frame 6 to fit"},
    };
    for (const Case& c : cases) {
        const CommandResult r = runFirelook(dir, "fit " + pkg + " " + c.args + " -o out.json");
        EXPECT_NE(r.exit_code, 0) << c.args;
        ASSERT_EQ(lines(r.err).size(), 1u) << c.args << ": " << r.err;
        EXPECT_NE(r.err.find(c.names), std::string::npos) << c.args << ": " << r.err;
    }
    EXPECT_EQ(dir.entries(), (std::vector<std::string>{"black.exr", "small.exr", "zero.png"}));
}

}  // namespace
}  // namespace firelook::fit
