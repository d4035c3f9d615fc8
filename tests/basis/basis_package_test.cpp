// The baked basis in a .firelook package (runtime/basis/basis_package.h): factors written with
// ContainerWriter + writeFrameFactors + makeMetadata come back within the frame codec's bounds
// (tests/basis/frame_codec_test.cpp checks the bounds themselves), packages of layout 1 are still
// read, and inconsistent packages fail with errors that name the file.
#include "basis/basis_package.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <glm/gtc/packing.hpp>
#include <nlohmann/json.hpp>

#include "../support/error_code.h"
#include "../support/temp_dir.h"
#include "../world/synthetic_package.h"
#include "package/error.h"
#include "reference_kernels.h"

namespace firelook::basis {
namespace {

using firelook::testing::TempDir;

BakeDescription packageDescription() {
    BakeDescription d;
    d.bins = {0.0, 3.0, 2};
    d.albedo = 0.7;
    d.axes = {{1.0, 2.0}, {4.0}, {1.5}};
    d.alpha_thresholds = {1.0, 1.5, 2.0};
    d.light_directions = {{0.0, 0.0, -1.0}};
    d.width = 5;
    d.height = 3;
    return d;
}

// Factors with every value distinct (and a few awkward floats) so a misplaced byte shows.
FrameFactors packageFactors(const BakeDescription& d, int frame, int rank) {
    FrameFactors f = emptyFrameFactors(d, frame, rank);
    for (int i = 0; i < f.pixels * rank; ++i)
        f.u_half.push_back(static_cast<uint16_t>(0x3000 + 37 * i + frame));
    for (int i = 0; i < f.columns * rank; ++i) f.svt.push_back(0.5f * i - 3.25f + frame);
    if (!f.svt.empty()) f.svt[0] = -0.0f;
    if (f.svt.size() > 1) f.svt[1] = 1e-42f;  // a denormal
    for (int i = 0; i < f.pixels; ++i) f.depth_b.push_back(0.125f * i + frame);
    // O_a in [-O_b, O_b] (f is a sigmoid in [-1, 1]), decreasing with the threshold.
    for (size_t i = 0; i < f.pixels * d.alpha_thresholds.size(); ++i)
        f.depth_a.push_back((0.9f - 0.7f * float(i / f.pixels) - 0.01f * float(i % f.pixels)) *
                                  f.depth_b[i % f.pixels]);
    return f;
}

template <typename T>
bool sameBytes(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

void writePackage(const std::filesystem::path& file, BakeDescription d,
                  const std::vector<FrameFactors>& frames,
                  const std::string& extra = R"({"provenance": {"tool": "basis_package_test"}})") {
    package::ContainerWriter writer(file);
    for (const FrameFactors& f : frames) {
        writeFrameFactors(writer, d, f);
        if (!d.findFrame(f.frame)) d.frames.push_back({f.frame, f.rank});
    }
    writer.addMetadata(makeMetadata(d, extra));
    writer.commit();
}

std::string packageErrorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}

// The factors as the codec stores them; alpha within what the codec reports for the frame.
TEST(BasisReader, FactorsRoundTrip) {
    TempDir dir;
    const BakeDescription d = packageDescription();
    const std::vector<FrameFactors> frames = {packageFactors(d, 1, 3), packageFactors(d, 4, 1), packageFactors(d, 7, 0)};
    writePackage(dir / "a.firelook", d, frames);

    const BasisReader package = BasisReader::open(dir / "a.firelook");
    EXPECT_EQ(package.file(), dir / "a.firelook");
    EXPECT_EQ(package.layoutVersion(), kBasisLayoutVersion);
    EXPECT_EQ(package.description().width, d.width);
    EXPECT_EQ(package.description().axes.temperature_threshold, d.axes.temperature_threshold);
    EXPECT_EQ(package.description().frames.size(), 3u);
    const nlohmann::json meta = nlohmann::json::parse(package.metadataJson());
    EXPECT_EQ(meta.at("format"), "firelook-basis");
    EXPECT_EQ(meta.at("provenance").at("tool"), "basis_package_test");
    for (const FrameFactors& written : frames) {
        const FrameFactors read = package.loadFrame(written.frame);
        const EncodedFrame encoded = encodeFrame(d, written, {});
        const FrameFactors direct = decodeFrame(d, written.frame, written.rank, encoded.u, encoded.svt,
                                                encoded.depths, "direct");
        EXPECT_EQ(read.frame, written.frame);
        EXPECT_EQ(read.pixels, written.pixels);
        EXPECT_EQ(read.columns, written.columns);
        EXPECT_EQ(read.rank, written.rank);
        // What the package holds is exactly the codec's bytes.
        EXPECT_TRUE(sameBytes(read.svt, direct.svt)) << "frame " << written.frame;
        EXPECT_TRUE(sameBytes(read.u_half, direct.u_half)) << "frame " << written.frame;
        EXPECT_TRUE(sameBytes(read.depth_b, direct.depth_b)) << "frame " << written.frame;
        EXPECT_TRUE(sameBytes(read.depth_a, direct.depth_a)) << "frame " << written.frame;
        for (const ExtinctionParams e : {ExtinctionParams{1.0f, 4.0f, 1.5f}, ExtinctionParams{1.7f, 4.0f, 1.5f}})
            for (int p = 0; p < d.pixelCount(); ++p)
                EXPECT_NEAR(reference::pixelAlpha(d, read, p, e), reference::pixelAlpha(d, written, p, e),
                            encoded.alpha_bound + 1e-6);
    }
}

// A package of layout 1 (U and depths as half, written by the code of that time from the
// synthetic frames of tests/world/synthetic_package.h: 8x6, 4 bins, ranks 4 and 3, 3 thresholds,
// seed 7) reads back exactly as it was stored.
TEST(BasisReader, ReadsLayout1) {
    const BasisReader package = BasisReader::open(FIRELOOK_TEST_DATA_DIR "/basis/layout1.firelook");
    EXPECT_EQ(package.layoutVersion(), 1);
    const BakeDescription& d = package.description();
    ASSERT_EQ(d.frames.size(), 2u);
    uint64_t state = 7 * 1000003ull + 1;  // syntheticFrame's generator for frame 1
    auto next = [&state] { return firelook::testing::syntheticValue(state); };
    const FrameFactors f = package.loadFrame(1);
    ASSERT_EQ(f.rank, 4);
    for (uint16_t u : f.u_half) EXPECT_EQ(u, glm::packHalf1x16(next() - 0.5f));
    for (float v : f.svt) EXPECT_EQ(v, 2.0f * next() - 1.0f);
    for (float v : f.depth_b) EXPECT_EQ(v, glm::unpackHalf1x16(glm::packHalf1x16(2.0f * next())));
    EXPECT_NO_THROW(package.loadFrame(2));
}

// Optical depths beyond the largest half (a density of 1e6 over a unit path) read back finite:
// the transmittance is 0 for any extinction above 0.0016 either way, so alpha is 1.
TEST(BasisReader, HugeOpticalDepthsStayFinite) {
    TempDir dir;
    const BakeDescription d = packageDescription();
    FrameFactors f = packageFactors(d, 1, 1);
    for (size_t i = 0; i < f.depth_b.size(); ++i) f.depth_b[i] = i % 2 ? 1e30f : 7e4f;
    for (size_t i = 0; i < f.depth_a.size(); ++i) {
        const float o_b = f.depth_b[i % f.pixels];
        f.depth_a[i] = (i % 3 == 0 ? 1.0f : i % 3 == 1 ? -1.0f : 0.5f) * o_b;  // all flame, all smoke, 3/4 flame
    }
    writePackage(dir / "a.firelook", d, {f});
    const FrameFactors read = BasisReader::open(dir / "a.firelook").loadFrame(1);
    for (size_t i = 0; i < read.depth_b.size(); ++i) EXPECT_EQ(read.depth_b[i], 65504.0f) << i;
    for (size_t i = 0; i < read.depth_a.size(); ++i) ASSERT_TRUE(std::isfinite(read.depth_a[i])) << i;
    for (int p = 0; p < d.pixelCount(); ++p)
        EXPECT_EQ(reference::pixelAlpha(d, read, p, {1.5f, 4.0f, 1.5f}), 1.0f) << p;
}

TEST(BasisReader, MissingFrameNamesTheFile) {
    TempDir dir;
    const BakeDescription d = packageDescription();
    writePackage(dir / "a.firelook", d, {packageFactors(d, 1, 2)});
    const BasisReader package = BasisReader::open(dir / "a.firelook");
    const std::string e = packageErrorOf([&] { package.loadFrame(2); });
    EXPECT_NE(e.find((dir / "a.firelook").string()), std::string::npos) << e;
    EXPECT_NE(e.find("frame 2"), std::string::npos) << e;
}

TEST(BasisReader, WrongSectionSizeNamesTheFileAndSection) {
    TempDir dir;
    BakeDescription d = packageDescription();
    d.frames = {{1, 3}};  // the description claims rank 3, the factors hold rank 2
    writePackage(dir / "a.firelook", d, {packageFactors(d, 1, 2)});
    const BasisReader package = BasisReader::open(dir / "a.firelook");
    const std::string e = packageErrorOf([&] { package.loadFrame(1); });
    EXPECT_NE(e.find((dir / "a.firelook").string()), std::string::npos) << e;
    EXPECT_NE(e.find("UFAC"), std::string::npos) << e;
}

// Regression: writeFrameFactors once read past depth_b (AddressSanitizer) when depth_a
// was not a whole number of depth images; every size is now checked before anything is written.
TEST(BasisReader, InconsistentFactorsAreRefusedByTheWriter) {
    TempDir dir;
    const BakeDescription d = packageDescription();
    FrameFactors f = packageFactors(d, 1, 2);
    f.depth_a.pop_back();
    package::ContainerWriter writer(dir / "a.firelook");
    EXPECT_ERROR_CODE(firelook::ErrorCode::InvalidArgument, writeFrameFactors(writer, d, f));
    f = packageFactors(d, 2, 2);
    f.u_half.pop_back();
    EXPECT_ERROR_CODE(firelook::ErrorCode::InvalidArgument, writeFrameFactors(writer, d, f));
}

TEST(BasisReader, MissingSectionNamesTheFileAndSection) {
    TempDir dir;
    BakeDescription d = packageDescription();
    d.frames = {{1, 2}};
    {
        package::ContainerWriter writer(dir / "a.firelook");
        const FrameFactors f = packageFactors(d, 1, 2);
        writer.addSection(kSectionU, 1, std::as_bytes(std::span<const uint16_t>(f.u_half)));
        writer.addMetadata(makeMetadata(d, ""));
        writer.commit();
    }
    const std::string e = packageErrorOf([&] { BasisReader::open(dir / "a.firelook").loadFrame(1); });
    EXPECT_NE(e.find((dir / "a.firelook").string()), std::string::npos) << e;
    EXPECT_NE(e.find("SVTF"), std::string::npos) << e;
}

TEST(BasisReader, BadMetadataNamesTheFile) {
    TempDir dir;
    const auto path = dir / "a.firelook";
    {
        package::ContainerWriter writer(path);
        writer.addSection(kSectionU, 1, {});
        writer.commit();
    }
    std::string e = packageErrorOf([&] { BasisReader::open(path); });
    EXPECT_NE(e.find(path.string()), std::string::npos) << e;
    EXPECT_NE(e.find("metadata"), std::string::npos) << e;

    {
        package::ContainerWriter writer(path);
        writer.addMetadata(R"({"format": "something-else", "bake": {}})");
        writer.commit();
    }
    e = packageErrorOf([&] { BasisReader::open(path); });
    EXPECT_NE(e.find(path.string()), std::string::npos) << e;
    EXPECT_NE(e.find("firelook-basis"), std::string::npos) << e;

    {
        package::ContainerWriter writer(path);
        BakeDescription d = packageDescription();
        d.width = 0;
        writer.addMetadata(makeMetadata(d, ""));
        writer.commit();
    }
    e = packageErrorOf([&] { BasisReader::open(path); });
    EXPECT_NE(e.find(path.string()), std::string::npos) << e;

    e = packageErrorOf([&] { BasisReader::open(dir / "missing.firelook"); });
    EXPECT_NE(e.find("missing.firelook"), std::string::npos) << e;
}

TEST(BasisReader, MetadataExtraMembersSitBesideBake) {
    const std::string meta = makeMetadata(packageDescription(), R"({"errors": [1, 2], "camera": {"source": "x"}})");
    const nlohmann::json doc = nlohmann::json::parse(meta);
    EXPECT_EQ(doc.at("format"), "firelook-basis");
    EXPECT_EQ(doc.at("version"), kBasisLayoutVersion);
    EXPECT_TRUE(doc.at("bake").is_object());
    EXPECT_EQ(doc.at("errors").size(), 2u);
    EXPECT_EQ(doc.at("camera").at("source"), "x");
    EXPECT_NO_THROW(parseBakeDescription(doc.at("bake").dump(), "meta"));
}

}  // namespace
}  // namespace firelook::basis
