#include "image/image_io.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <limits>
#include <string>

#include "../support/error_code.h"
#include "../support/temp_dir.h"
#include "image/srgb.h"

namespace firelook::image {
namespace {

using testing::TempDir;

// Largest error of 8-bit sRGB quantisation seen in linear units: half a code step (0.5/255) times
// the steepest slope of the decoding curve, 2.4/1.055 at full scale.
constexpr double kSrgb8LinearBound = 2.4 / 1.055 * 0.5 / 255.0;
// Alpha is stored linearly in 8 bits: half a code step.
constexpr double kAlpha8Bound = 0.5 / 255.0;
// Float-to-float slack for the arithmetic on top of the quantisation bounds.
constexpr double kFloatSlack = 1e-6;

// HDR content: values well above 1, tiny values, exact zeros, and alpha across [0, 1].
ImageRGBA makeHdrImage(int width, int height) {
    ImageRGBA image(width, height);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const float alpha = static_cast<float>(x + y) / static_cast<float>(width + height - 2);
            auto pixel = image.at(x, y);
            pixel[0] = alpha * (0.001f + 37.25f * static_cast<float>(x));
            pixel[1] = alpha * 0.3f * static_cast<float>(y) / 7.0f;
            pixel[2] = 1e-5f * static_cast<float>(x * y);
            pixel[3] = alpha;
        }
    }
    return image;
}

// Display-range content for PNG: straight colour in [0, 1] times alpha.
ImageRGBA makeDisplayImage(int width, int height) {
    ImageRGBA image(width, height);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const float alpha = 0.1f + 0.9f * static_cast<float>(y) / static_cast<float>(height - 1);
            const float colour[3] = {static_cast<float>(x) / static_cast<float>(width - 1), 0.5f,
                                     1.0f - static_cast<float>(x) / static_cast<float>(width - 1)};
            auto pixel = image.at(x, y);
            for (int c = 0; c < 3; ++c) pixel[c] = colour[c] * alpha;
            pixel[3] = alpha;
        }
    }
    return image;
}

ImageRGBA solidImage(int width, int height, std::array<float, 4> value) {
    ImageRGBA image(width, height);
    for (std::size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = value[i % 4];
    return image;
}

// Options built by assignment: GCC 12 warns (-Wmissing-field-initializers) on designated
// initialisers that leave out a member, even one with a default.
WriteOptions floatExr() {
    WriteOptions options;
    options.exr_pixel_type = ExrPixelType::Float;
    return options;
}

WriteOptions pngExposure(double stops) {
    WriteOptions options;
    options.png_exposure_stops = stops;
    return options;
}

std::string readBytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(ImageIo, ExrFloatRoundTripIsBitExact) {
    TempDir dir;
    const ImageRGBA original = makeHdrImage(13, 7);
    writeImage(dir.path() / "float.exr", original, floatExr());
    const ImageRGBA read = readImage(dir.path() / "float.exr");
    ASSERT_EQ(read.width, 13);
    ASSERT_EQ(read.height, 7);
    ASSERT_EQ(read.pixels.size(), original.pixels.size());
    for (std::size_t i = 0; i < read.pixels.size(); ++i) EXPECT_EQ(read.pixels[i], original.pixels[i]) << i;
}

TEST(ImageIo, ExrHalfRoundTripWithinHalfPrecision) {
    TempDir dir;
    const ImageRGBA original = makeHdrImage(13, 7);
    writeImage(dir.path() / "half.exr", original);
    const ImageRGBA read = readImage(dir.path() / "half.exr");
    ASSERT_EQ(read.pixels.size(), original.pixels.size());
    for (std::size_t i = 0; i < read.pixels.size(); ++i) {
        const double value = original.pixels[i];
        // Half keeps 11 significant bits, so rounding to nearest is off by at most 2^-11 relative;
        // below the smallest normal half (2^-14) the spacing is fixed at 2^-24, so half of it, 2^-25.
        const double bound = std::max(std::fabs(value) * std::ldexp(1.0, -11), std::ldexp(1.0, -25));
        EXPECT_NEAR(read.pixels[i], value, bound) << "value index " << i;
    }
}

TEST(ImageIo, ExrStoresPremultipliedRgbaAsHalfWithZip) {
    TempDir dir;
    const auto path = dir.path() / "layout.exr";
    writeImage(path, makeHdrImage(4, 3));
    auto input = OIIO::ImageInput::open(path.string());
    ASSERT_TRUE(input) << OIIO::geterror();
    const OIIO::ImageSpec& spec = input->spec();
    ASSERT_EQ(spec.nchannels, 4);
    EXPECT_EQ(spec.channelnames[0], "R");
    EXPECT_EQ(spec.channelnames[1], "G");
    EXPECT_EQ(spec.channelnames[2], "B");
    EXPECT_EQ(spec.channelnames[3], "A");
    EXPECT_EQ(spec.alpha_channel, 3);
    EXPECT_EQ(spec.format, OIIO::TypeDesc::HALF);
    EXPECT_EQ(spec.get_string_attribute("compression"), "zip");
}

TEST(ImageIo, HalfOverflowIsRefusedButFloatKeepsIt) {
    TempDir dir;
    const ImageRGBA bright = solidImage(2, 2, {70000.0f, 1.0f, 1.0f, 1.0f});
    EXPECT_THROW(writeImage(dir.path() / "bright.exr", bright), ImageError);
    EXPECT_TRUE(dir.entries().empty());
    writeImage(dir.path() / "bright.exr", bright, floatExr());
    EXPECT_EQ(readImage(dir.path() / "bright.exr").at(1, 1)[0], 70000.0f);
}

TEST(ImageIo, PngRoundTripWithinEightBitQuantisation) {
    TempDir dir;
    const ImageRGBA original = makeDisplayImage(17, 9);
    writeImage(dir.path() / "display.png", original);
    const ImageRGBA read = readImage(dir.path() / "display.png");
    ASSERT_EQ(read.width, 17);
    ASSERT_EQ(read.height, 9);
    for (std::size_t i = 0; i < read.pixels.size(); i += 4) {
        EXPECT_NEAR(read.pixels[i + 3], original.pixels[i + 3], kAlpha8Bound + kFloatSlack)
            << "alpha " << i / 4;
        // Colour is stored divided by the stored alpha, so premultiplying on read undoes the alpha
        // rounding; what remains is the colour quantisation (scaled by alpha <= 1) plus, where alpha
        // rounded down and the straight colour was 1, the clamp: at most the alpha step.
        for (std::size_t c = 0; c < 3; ++c) {
            EXPECT_NEAR(read.pixels[i + c], original.pixels[i + c],
                        kSrgb8LinearBound + kAlpha8Bound + kFloatSlack)
                << "pixel " << i / 4 << " channel " << c;
        }
    }
}

TEST(ImageIo, PngStoresSrgbEncodedStraightColour) {
    TempDir dir;
    const auto path = dir.path() / "grey.png";
    // Mid grey 0.18 opaque, and the same straight colour at alpha 0.2 (premultiplied 0.036). Alpha
    // 0.2 is exactly code 51, so both store round(255 * srgb(0.18)) = round(117.65) = 118.
    ImageRGBA image(2, 1);
    std::copy_n(std::array<float, 4>{0.18f, 0.18f, 0.18f, 1.0f}.begin(), 4, image.at(0, 0).begin());
    std::copy_n(std::array<float, 4>{0.036f, 0.036f, 0.036f, 0.2f}.begin(), 4, image.at(1, 0).begin());
    writeImage(path, image);
    OIIO::ImageSpec keep_straight_alpha;  // OpenImageIO would otherwise premultiply on reading
    keep_straight_alpha.attribute("oiio:UnassociatedAlpha", 1);
    auto input = OIIO::ImageInput::open(path.string(), &keep_straight_alpha);
    ASSERT_TRUE(input) << OIIO::geterror();
    ASSERT_EQ(input->spec().nchannels, 4);
    unsigned char bytes[8] = {};
    ASSERT_TRUE(input->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT8, bytes));
    const unsigned char expected[8] = {118, 118, 118, 255, 118, 118, 118, 51};
    for (int i = 0; i < 8; ++i) EXPECT_EQ(bytes[i], expected[i]) << i;
}

TEST(ImageIo, PngExposureScalesLinearColour) {
    TempDir dir;
    const ImageRGBA image = solidImage(2, 2, {0.1f, 0.05f, 0.2f, 1.0f});
    writeImage(dir.path() / "up.png", image, pngExposure(2.0));
    writeImage(dir.path() / "down.png", image, pngExposure(-1.0));
    const ImageRGBA up_image = readImage(dir.path() / "up.png");
    const ImageRGBA down_image = readImage(dir.path() / "down.png");
    const auto up = up_image.at(0, 0);
    const auto down = down_image.at(0, 0);
    const float expected_up[3] = {0.4f, 0.2f, 0.8f};       // 2^2 = 4 times
    const float expected_down[3] = {0.05f, 0.025f, 0.1f};  // 2^-1 = half
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(up[c], expected_up[c], kSrgb8LinearBound + kFloatSlack) << c;
        EXPECT_NEAR(down[c], expected_down[c], kSrgb8LinearBound + kFloatSlack) << c;
    }
    EXPECT_EQ(up[3], 1.0f);
}

TEST(ImageIo, PngBackgroundCompositesAndWritesOpaque) {
    TempDir dir;
    const auto path = dir.path() / "over.png";
    // Exposure +1 applies to the fire, not to the background: 2 * 0.2 + (1 - 0.5) * 0.5 = 0.65, etc.
    WriteOptions options = pngExposure(1.0);
    options.png_background = std::array<float, 3>{0.5f, 0.3f, 0.1f};
    writeImage(path, solidImage(3, 2, {0.2f, 0.1f, 0.0f, 0.5f}), options);
    auto input = OIIO::ImageInput::open(path.string());
    ASSERT_TRUE(input) << OIIO::geterror();
    EXPECT_EQ(input->spec().nchannels, 3);
    input->close();
    const ImageRGBA read = readImage(path);
    const auto pixel = read.at(2, 1);
    EXPECT_NEAR(pixel[0], 0.65, kSrgb8LinearBound + kFloatSlack);
    EXPECT_NEAR(pixel[1], 0.35, kSrgb8LinearBound + kFloatSlack);
    EXPECT_NEAR(pixel[2], 0.05, kSrgb8LinearBound + kFloatSlack);
    EXPECT_EQ(pixel[3], 1.0f);
}

TEST(ImageIo, PngWithAlphaLosesEmissionWhereAlphaRoundsToZero) {
    TempDir dir;
    // Documented limitation of straight-alpha PNG: glow with alpha below half an 8-bit step is lost.
    writeImage(dir.path() / "glow.png", solidImage(1, 1, {0.5f, 0.2f, 0.1f, 0.001f}));
    const ImageRGBA read = readImage(dir.path() / "glow.png");
    const auto pixel = read.at(0, 0);
    for (int c = 0; c < 4; ++c) EXPECT_EQ(pixel[c], 0.0f) << c;
}

TEST(ImageIo, UpperCaseExtensionIsAccepted) {
    TempDir dir;
    writeImage(dir.path() / "LOUD.EXR", solidImage(1, 1, {1, 2, 3, 1}));
    EXPECT_EQ(readImage(dir.path() / "LOUD.EXR").at(0, 0)[2], 3.0f);
}

TEST(ImageIo, AtomicWriteLeavesOnlyTheTargetAndReplacesIt) {
    TempDir dir;
    const auto path = dir.path() / "frame.exr";
    writeImage(path, solidImage(2, 2, {1, 1, 1, 1}));
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"frame.exr"});
    writeImage(path, solidImage(2, 2, {0.5f, 0.5f, 0.5f, 1}));
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"frame.exr"});
    EXPECT_EQ(readImage(path).at(0, 0)[0], 0.5f);
}

TEST(ImageIo, FailedWriteKeepsTheOldFileAndLeavesNoTemporary) {
    TempDir dir;
    const auto path = dir.path() / "frame.png";
    writeImage(path, solidImage(2, 2, {0.5f, 0.5f, 0.5f, 1}));
    const std::string before = readBytes(path);
    ImageRGBA broken = solidImage(2, 2, {0.5f, 0.5f, 0.5f, 1});
    broken.at(1, 0)[1] = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(writeImage(path, broken), ImageError);
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"frame.png"});
    EXPECT_EQ(readBytes(path), before);
}

TEST(ImageIo, FailedRenameRemovesTheTemporary) {
    TempDir dir;
    // The target is a non-empty folder: the image itself is written, but it cannot be moved there.
    std::filesystem::create_directories(dir.path() / "taken.exr" / "inside");
    EXPECT_THROW(writeImage(dir.path() / "taken.exr", solidImage(2, 2, {1, 1, 1, 1})), ImageError);
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"taken.exr"});
}

TEST(ImageIo, MissingFolderIsAnErrorNamingTheFile) {
    TempDir dir;
    const auto path = dir.path() / "no-such-folder" / "frame.exr";
    try {
        writeImage(path, solidImage(1, 1, {1, 1, 1, 1}));
        FAIL() << "expected ImageError";
    } catch (const ImageError& error) {
        EXPECT_EQ(error.code(), ErrorCode::IoError);  // the temporary's (formats/common/atomic_file.h)
        EXPECT_NE(std::string(error.what()).find(path.string()), std::string::npos) << error.what();
    }
}

TEST(ImageIo, NonFiniteValuesAreRefusedNamingTheFileAndPixel) {
    TempDir dir;
    for (const float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                            -std::numeric_limits<float>::infinity()}) {
        for (const char* name : {"bad.exr", "bad.png"}) {
            ImageRGBA image = solidImage(3, 2, {0, 0, 0, 0});
            image.at(2, 1)[3] = bad;
            try {
                writeImage(dir.path() / name, image, floatExr());
                FAIL() << "expected ImageError for " << bad << " in " << name;
            } catch (const ImageError& error) {
                const std::string message = error.what();
                EXPECT_NE(message.find(name), std::string::npos) << message;
                EXPECT_NE(message.find("non-finite"), std::string::npos) << message;
                EXPECT_NE(message.find("pixel (2, 1) channel A"), std::string::npos) << message;
            }
        }
    }
    EXPECT_TRUE(dir.entries().empty());
}

TEST(ImageIo, UnknownExtensionIsAClearError) {
    TempDir dir;
    for (const char* name : {"frame.jpg", "frame", "frame.exr.bak"}) {
        try {
            writeImage(dir.path() / name, solidImage(1, 1, {1, 1, 1, 1}));
            FAIL() << "expected ImageError for " << name;
        } catch (const ImageError& error) {
            const std::string message = error.what();
            EXPECT_NE(message.find(name), std::string::npos) << message;
            EXPECT_NE(message.find("extension"), std::string::npos) << message;
        }
    }
    EXPECT_THROW(readImage(dir.path() / "frame.tif"), ImageError);
    EXPECT_TRUE(dir.entries().empty());
}

TEST(ImageIo, MalformedImagesAreRefused) {
    TempDir dir;
    ImageRGBA short_of_values = solidImage(2, 2, {1, 1, 1, 1});
    short_of_values.pixels.pop_back();
    EXPECT_THROW(writeImage(dir.path() / "short.exr", short_of_values), ImageError);
    EXPECT_THROW(writeImage(dir.path() / "empty.exr", ImageRGBA{}), ImageError);
    EXPECT_THROW(ImageRGBA(-1, 3), ImageError);
    EXPECT_TRUE(dir.entries().empty());
}

TEST(ImageIo, ReadingMissingOrCorruptFilesIsAnError) {
    TempDir dir;
    EXPECT_ERROR_CODE(ErrorCode::IoError, readImage(dir.path() / "absent.exr"));
    std::ofstream(dir.path() / "garbage.exr") << "not an image at all";
    EXPECT_ERROR_CODE(ErrorCode::BadImage, readImage(dir.path() / "garbage.exr"));
    try {
        readImage(dir.path() / "garbage.exr");
        FAIL() << "expected ImageError";
    } catch (const ImageError& error) {
        EXPECT_NE(std::string(error.what()).find("garbage.exr"), std::string::npos) << error.what();
    }
}

}  // namespace
}  // namespace firelook::image
