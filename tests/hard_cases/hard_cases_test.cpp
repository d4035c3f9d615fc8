// the hard cases of docs/testing.md across the whole pipeline: tiny VDB files written here with
// OpenVDB -> firelook::bake::bakePackage -> BasisReader::open / loadFrame -> renderLookImage.
// (tests/bake/hard_cases_test.cpp covers the same cases at the tracer level, without files.)
//
// Every rendered image is checked the same way: no NaN or Inf, radiance >= 0, alpha in [0, 1].
// Wrong input must fail with an exception whose message names the file, and leave no output.
// Sizes are tiny (8x8 images, 2000 photons, 1-2 point axes) so the suite stays fast under ASan; a
// watchdog fails any test that runs longer than kHangSeconds (a hang is a failure, not a timeout).
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <thread>
#include <vector>

#include "../vdb/vdb_test_files.h"
#include "bake/bake_pipeline.h"
#include "basis/basis_package.h"
#include "basis/look_renderer.h"
#include "look/look.h"
#include "look/look_model.h"
#include "package/error.h"
#include "package/container_writer.h"
#include "render/camera.h"
#include "vdb/vdb_error.h"

namespace firelook {
namespace {

namespace fs = std::filesystem;
using vdb::testing::makeGrid;
using vdb::testing::TempDir;
using vdb::testing::Voxels;
using vdb::testing::writeVdb;

constexpr int kHangSeconds = 60;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// ---- watchdog: a hang fails the suite with the test's name instead of waiting for ctest ----------

std::atomic<long> g_test_started{0};  // seconds since epoch; 0 = no test running
std::atomic<const char*> g_test_name{nullptr};

class Watchdog : public ::testing::EmptyTestEventListener {
    void OnTestStart(const ::testing::TestInfo& info) override {
        g_test_name = info.name();
        g_test_started = now();
    }
    void OnTestEnd(const ::testing::TestInfo&) override { g_test_started = 0; }

  public:
    static long now() {
        return std::chrono::duration_cast<std::chrono::seconds>(std::chrono::steady_clock::now().time_since_epoch())
            .count();
    }
};

const bool g_watchdog_installed = [] {
    ::testing::UnitTest::GetInstance()->listeners().Append(new Watchdog);
    std::thread([] {
        for (;;) {
            std::this_thread::sleep_for(std::chrono::seconds(1));
            const long started = g_test_started;
            if (started != 0 && Watchdog::now() - started > kHangSeconds) {
                std::fprintf(stderr, "hard case %s hung (> %d s)\n", g_test_name.load(), kHangSeconds);
                std::_Exit(3);
            }
        }
    }).detach();
    return true;
}();

// ---- building sequences -------------------------------------------------------------------------

// An n^3 block of voxels starting at `corner`, value f(i, j, k) (local indices).
template <typename F>
Voxels block(int n, F f, openvdb::Coord corner = openvdb::Coord(0)) {
    Voxels voxels;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            for (int k = 0; k < n; ++k) voxels.push_back({corner.offsetBy(i, j, k), f(i, j, k)});
    return voxels;
}

Voxels constant(int n, float value) {
    return block(n, [value](int, int, int) { return value; });
}

// Temperatures rising along x from 0 to 3 over the block: smoke on one side, flame on the other.
Voxels ramp(int n) {
    return block(n, [n](int i, int, int) { return 3.0f * float(i) / float(n - 1); });
}

std::string frameName(int frame) {
    char name[32];
    std::snprintf(name, sizeof name, "fire_%04d.vdb", frame);
    return name;
}

void writeFrame(const fs::path& folder, int frame, const Voxels& density, const Voxels& temperature,
                double voxel_size = 0.1, float temperature_background = 0.0f) {
    writeVdb(folder / frameName(frame), {makeGrid("density", density, voxel_size),
                                         makeGrid("temperature", temperature, voxel_size, temperature_background)});
}

// A tiny bake: 8x8 pixels, 4 bins over [0, 3], a 2x1x1 grid, few photons, 3 scattering orders.
bake::BakeConfig tinyConfig() {
    bake::BakeConfig c;
    c.scene.width = 8;
    c.scene.height = 8;
    c.bins = 4;
    c.t_lo = 0.0;
    c.t_hi = 3.0;
    c.albedo = 0.7;
    c.axes = {{1.0, 2.0}, {4.0}, {1.5}};
    c.alpha_threshold_samples = 3;
    c.trace.photons_primary = 2000;
    c.trace.photons_per_order = 1000;
    c.trace.photon_noise_target = 0.0;  // as many photons as given: the suite stays fast
    c.trace.max_orders = 3;
    c.trace.cell_voxels = 4;
    return c;
}

// A camera (position, target, vertical fov in degrees) in front of a 6-voxel block of edge 0.1.
std::array<double, 7> frontCamera() { return {0.25, 0.25, 2.0, 0.25, 0.25, 0.25, 30.0}; }

// ---- checking images ----------------------------------------------------------------------------

struct Image {
    std::vector<float> rgba;
    float maxRadiance() const {
        float m = 0.0f;
        for (std::size_t i = 0; i < rgba.size(); ++i)
            if (i % 4 != 3) m = std::max(m, rgba[i]);
        return m;
    }
    float maxAlpha() const {
        float m = 0.0f;
        for (std::size_t i = 3; i < rgba.size(); i += 4) m = std::max(m, rgba[i]);
        return m;
    }
    float minAlpha() const {
        float m = 1.0f;
        for (std::size_t i = 3; i < rgba.size(); i += 4) m = std::min(m, rgba[i]);
        return m;
    }
    double sumRadiance() const {
        double s = 0.0;
        for (std::size_t i = 0; i < rgba.size(); ++i)
            if (i % 4 != 3) s += rgba[i];
        return s;
    }
};

void expectSane(const Image& image, const std::string& what) {
    for (std::size_t i = 0; i < image.rgba.size(); ++i) {
        const float v = image.rgba[i];
        ASSERT_TRUE(std::isfinite(v)) << what << ": value " << i << " is " << v;
        if (i % 4 == 3) {
            ASSERT_GE(v, 0.0f) << what << ": alpha of pixel " << i / 4;
            ASSERT_LE(v, 1.0f) << what << ": alpha of pixel " << i / 4;
        } else {
            ASSERT_GE(v, 0.0f) << what << ": radiance " << i;
        }
    }
}

// The package's default look, optionally changed, with the package's albedo.
Look packageLook(const basis::BasisReader& package) {
    return parseLook(package.description().default_look_json, package.file().string());
}

Image render(const basis::BasisReader& package, int frame, const Look& look) {
    const basis::ResidentFrame resident = package.loadResidentFrame(frame, std::pmr::get_default_resource());
    Image image;
    image.rgba.assign(static_cast<std::size_t>(package.description().pixelCount()) * 4, -1.0f);
    basis::renderLookImage(package.description(), resident, look, image.rgba);
    expectSane(image, package.file().filename().string() + " frame " + std::to_string(frame));
    return image;
}

// Bakes `folder` into folder/../out.firelook and renders every frame with the default look.
struct Baked {
    fs::path file;
    bake::BakeReport report;
};

Baked bakeInto(const TempDir& dir, const fs::path& sequence, const bake::BakeConfig& config) {
    Baked b;
    b.file = dir / "out.firelook";
    b.report = bake::bakePackage(sequence.string(), b.file, config, "hard-cases");
    return b;
}

std::vector<std::string> entries(const fs::path& folder) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(folder)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

// Runs `f`, expecting an exception of type E whose message contains every one of `parts`.
template <typename E, typename F>
void expectErrorNaming(F&& f, std::initializer_list<std::string> parts) {
    try {
        f();
        ADD_FAILURE() << "no exception; expected one naming " << *parts.begin();
    } catch (const E& e) {
        for (const std::string& part : parts) EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "unexpected exception type: " << e.what();
    }
}

// ---- the cases ----------------------------------------------------------------------------------

TEST(HardCases, EmptyVolumeInEveryFrame) {
    TempDir dir;
    const fs::path seq = dir / "seq";
    fs::create_directories(seq);
    for (int f = 1; f <= 2; ++f) writeFrame(seq, f, {}, constant(3, 1.0f));
    // The default camera frames the data; with nothing in any frame that is a clear error.
    expectErrorNaming<std::runtime_error>([&] { bakeInto(dir, seq, tinyConfig()); }, {seq.string(), "empty"});
    EXPECT_EQ(entries(dir.path()), std::vector<std::string>{"seq"}) << "no output left behind";
    // With a camera given, the bake succeeds: black, transparent frames.
    bake::BakeConfig config = tinyConfig();
    config.scene.camera = frontCamera();
    const Baked b = bakeInto(dir, seq, config);
    const basis::BasisReader package = basis::BasisReader::open(b.file);
    ASSERT_EQ(package.description().frames.size(), 2u);
    for (int f = 1; f <= 2; ++f) {
        const Image image = render(package, f, packageLook(package));
        EXPECT_EQ(image.maxRadiance(), 0.0f);
        EXPECT_EQ(image.maxAlpha(), 0.0f);
    }
}

// All voxels below every T_c (smoke) or above (flame). Bins are 16 over [0, 3] (dT = 0.1875), voxels
// sit 1.45 from the look's T_c = 1.5, so |f| >= tanh(1.45 / 0.375) = 0.9991 and alpha depends only on
// k_s (smoke) or k_f (flame) to within 0.1% of the optical depth. The temperature grid's background
// is the same temperature, so trilinear interpolation at the block's border stays on one side of T_c.
TEST(HardCases, AllVoxelsBelowOrAboveTheThreshold) {
    for (const float t : {0.05f, 2.95f}) {
        const bool smoke = t < 1.5f;
        TempDir dir;
        const fs::path seq = dir / "seq";
        fs::create_directories(seq);
        writeFrame(seq, 1, constant(6, 2.0f), constant(6, t), 0.1, t);
        bake::BakeConfig config = tinyConfig();
        config.bins = 16;
        config.axes = {{1.0, 2.0}, {1.0, 4.0}, {0.5, 3.0}};
        const Baked b = bakeInto(dir, seq, config);
        const basis::BasisReader package = basis::BasisReader::open(b.file);
        Look look = packageLook(package);
        look.temperature_threshold = 1.5;
        look.smoke_extinction = 4.0;
        look.flame_extinction = 0.5;
        const Image base = render(package, 1, look);
        EXPECT_GT(base.maxAlpha(), 0.1f) << "the block is seen";
        // Changing the extinction of the other kind of matter hardly changes alpha.
        Look other = look;
        (smoke ? other.flame_extinction : other.smoke_extinction) = smoke ? 3.0 : 1.0;
        const Image changed = render(package, 1, other);
        for (std::size_t i = 3; i < base.rgba.size(); i += 4)
            EXPECT_NEAR(changed.rgba[i], base.rgba[i], 3e-3) << (smoke ? "smoke" : "flame") << " pixel " << i / 4;
        // Changing its own extinction does.
        Look own = look;
        (smoke ? own.smoke_extinction : own.flame_extinction) = smoke ? 1.0 : 3.0;
        const Image own_image = render(package, 1, own);
        EXPECT_GT(std::abs(own_image.maxAlpha() - base.maxAlpha()), 0.01f);
    }
}

TEST(HardCases, ZeroSmokeOrFlameExtinction) {
    TempDir dir;
    const fs::path seq = dir / "seq";
    fs::create_directories(seq);
    writeFrame(seq, 1, constant(6, 1.0f), ramp(6));
    bake::BakeConfig config = tinyConfig();
    config.axes = {{1.5}, {0.0, 2.0}, {0.0, 2.0}};
    const Baked b = bakeInto(dir, seq, config);
    const basis::BasisReader package = basis::BasisReader::open(b.file);
    for (const auto& [ks, kf] : {std::pair{0.0, 0.0}, std::pair{0.0, 2.0}, std::pair{2.0, 0.0}}) {
        Look look = packageLook(package);
        look.smoke_extinction = ks;
        look.flame_extinction = kf;
        const Image image = render(package, 1, look);
        if (ks == 0.0 && kf == 0.0) {
            EXPECT_EQ(image.maxAlpha(), 0.0f) << "no extinction: fully transparent";
            EXPECT_GT(image.maxRadiance(), 0.0f) << "the flame still glows";
        } else {
            EXPECT_GT(image.maxAlpha(), 0.0f);
        }
    }
}

TEST(HardCases, VeryLargeExtinctionUnderflowsTransmittance) {
    TempDir dir;
    const fs::path seq = dir / "seq";
    fs::create_directories(seq);
    writeFrame(seq, 1, constant(6, 5.0f), ramp(6));
    bake::BakeConfig config = tinyConfig();
    config.axes = {{1.5}, {1e6}, {1e7}};
    const Baked b = bakeInto(dir, seq, config);
    const basis::BasisReader package = basis::BasisReader::open(b.file);
    const Image image = render(package, 1, packageLook(package));
    EXPECT_EQ(image.maxAlpha(), 1.0f) << "exp(-1e6) underflows to 0: fully opaque";
}

TEST(HardCases, AlbedoZeroAndOne) {
    for (const double albedo : {0.0, 1.0}) {
        TempDir dir;
        const fs::path seq = dir / "seq";
        fs::create_directories(seq);
        writeFrame(seq, 1, constant(6, 2.0f), ramp(6));
        bake::BakeConfig config = tinyConfig();
        config.albedo = albedo;
        const Baked b = bakeInto(dir, seq, config);
        const basis::BasisReader package = basis::BasisReader::open(b.file);
        EXPECT_EQ(package.description().albedo, albedo);
        Look look = packageLook(package);
        EXPECT_EQ(look.albedo, albedo) << "the recorded default look carries the baked albedo";
        const Image image = render(package, 1, look);
        EXPECT_GT(image.maxAlpha(), 0.0f);
        // Another albedo is refused, naming the look and the key.
        look.albedo = 0.5;
        look.source_name = "my-look.json";
        expectErrorNaming<LookError>([&] { render(package, 1, look); }, {"my-look.json", "albedo"});
    }
}

TEST(HardCases, OneBinAndManyBins) {
    for (const int bins : {1, 64}) {
        TempDir dir;
        const fs::path seq = dir / "seq";
        fs::create_directories(seq);
        writeFrame(seq, 1, constant(6, 1.0f), ramp(6));
        bake::BakeConfig config = tinyConfig();
        config.bins = bins;
        const Baked b = bakeInto(dir, seq, config);
        const basis::BasisReader package = basis::BasisReader::open(b.file);
        EXPECT_EQ(package.description().bins.count, bins);
        const Image image = render(package, 1, packageLook(package));
        EXPECT_GT(image.maxRadiance(), 0.0f) << bins << " bins";
        // A look with "bins" emissivity of the wrong length is refused, naming the look.
        Look wrong = packageLook(package);
        wrong.emission = EmissionBins{std::vector<Rgb>(static_cast<std::size_t>(bins + 1), Rgb(1.0f))};
        wrong.source_name = "bins-look.json";
        expectErrorNaming<LookError>([&] { render(package, 1, wrong); }, {"bins-look.json", "bins"});
        // One entry per bin with a sharp step in the middle: fitted without negative emission.
        EmissionBins step;
        for (int i = 0; i < bins; ++i) step.emissivity.push_back(i < bins / 2 ? Rgb(0.0f) : Rgb(20.0f, 8.0f, 1.0f));
        Look stepped = packageLook(package);
        stepped.emission = step;
        render(package, 1, stepped);
    }
}

// The same block with temperatures in units 1000x smaller and 10^4x larger: bins, T_c axis and look
// scaled alike, so alpha (exact ray marching, no Monte Carlo) must match the unit-scale bake.
TEST(HardCases, TinyAndHugeTemperatureUnits) {
    std::vector<Image> alphas;
    for (const double unit : {1.0, 1e-3, 1e4}) {
        TempDir dir;
        const fs::path seq = dir / "seq";
        fs::create_directories(seq);
        writeFrame(seq, 1, constant(6, 2.0f), ramp(6));
        bake::BakeConfig config = tinyConfig();
        config.read.temperature_scale = unit;
        config.t_lo.reset();  // the data's own range: [0, 3 unit]
        config.t_hi.reset();
        config.axes = {{1.0 * unit, 2.0 * unit}, {4.0}, {1.5}};
        const Baked b = bakeInto(dir, seq, config);
        const basis::BasisReader package = basis::BasisReader::open(b.file);
        EXPECT_NEAR(package.description().bins.t_hi, 3.0 * unit, 1e-6 * unit);
        Look look = packageLook(package);
        look.temperature_threshold = 1.4 * unit;
        look.emission = EmissionStops{{{1.4 * unit, Rgb(0.0f)}, {3.0 * unit, Rgb(10.0f, 7.0f, 3.0f)}}};
        const Image image = render(package, 1, look);
        EXPECT_GT(image.maxRadiance(), 0.0f) << "unit " << unit;
        EXPECT_GT(image.maxAlpha(), 0.1f) << "unit " << unit;
        alphas.push_back(image);
    }
    // The bakes differ only by float rounding of the scaled temperatures (~6e-8 relative): the same
    // photons (same seed) land in the same bins, so the images agree to rounding. Measured: alpha
    // bit-identical, every radiance within 1.7e-7 of the peak, sum ratios 1 +- 1.4e-7. Alpha: 1e-4
    // (stored depths are halfs; a rounding difference that moved one across a half's rounding
    // boundary would show as up to tau exp(-tau) 2^-10 <= 3.6e-4, and none does), while a T_c, bin or
    // look that missed the scaling would mix smoke (k_s 4) and flame (k_f 1.5) differently and move
    // alpha far more. Radiance: 1e-4 of the sum (it was 0.15), ~700 times the measured difference,
    // still far below what one bin landing elsewhere would do (a bin is a quarter of the range).
    for (std::size_t u = 1; u < alphas.size(); ++u) {
        double worst_alpha = 0.0;
        for (std::size_t i = 3; i < alphas[0].rgba.size(); i += 4) {
            worst_alpha = std::max(worst_alpha, static_cast<double>(std::abs(alphas[u].rgba[i] - alphas[0].rgba[i])));
            EXPECT_NEAR(alphas[u].rgba[i], alphas[0].rgba[i], 1e-4) << "unit " << u << " pixel " << i / 4;
        }
        std::printf("[measured] unit %zu: worst alpha difference %.2e, radiance sum ratio %.8f\n", u, worst_alpha,
                    alphas[u].sumRadiance() / alphas[0].sumRadiance());
        EXPECT_NEAR(alphas[u].sumRadiance(), alphas[0].sumRadiance(), 1e-4 * alphas[0].sumRadiance()) << "unit " << u;
    }
}

TEST(HardCases, EmissivityWithASharpStep) {
    TempDir dir;
    const fs::path seq = dir / "seq";
    fs::create_directories(seq);
    writeFrame(seq, 1, constant(6, 1.0f), ramp(6));
    bake::BakeConfig config = tinyConfig();
    config.bins = 16;
    const Baked b = bakeInto(dir, seq, config);
    const basis::BasisReader package = basis::BasisReader::open(b.file);
    Look look = packageLook(package);
    look.emission = EmissionStops{{{1.5, Rgb(0.0f)}, {1.5, Rgb(50.0f, 20.0f, 5.0f)}}};
    const Image image = render(package, 1, look);
    EXPECT_GT(image.maxRadiance(), 0.0f);
}

// NaN, Inf and negative densities / temperatures: cleaned and counted by default (the package's
// provenance records the counts); refused with the count and the file under NonFinitePolicy::Refuse.
TEST(HardCases, NonFiniteAndNegativeValuesAreCleanedAndCounted) {
    TempDir dir;
    const fs::path seq = dir / "seq";
    fs::create_directories(seq);
    Voxels density = constant(6, 1.0f), temperature = ramp(6);
    density[0].second = kNaN;
    density[7].second = kInf;
    density[8].second = -kInf;
    density[20].second = -0.5f;
    density[21].second = -3.0f;
    temperature[30].second = kNaN;
    temperature[31].second = kInf;
    writeFrame(seq, 1, density, temperature);
    const Baked b = bakeInto(dir, seq, tinyConfig());
    const basis::BasisReader package = basis::BasisReader::open(b.file);
    const nlohmann::json meta = nlohmann::json::parse(package.metadataJson());
    const nlohmann::json& source = meta.at("provenance").at("sources").at(0);
    EXPECT_EQ(source.at("cleaned_non_finite").get<int>(), 5) << source.dump();
    // -Inf is non-finite (counted there), so two negative finite densities remain.
    EXPECT_EQ(source.at("cleaned_negative_density").get<int>(), 2) << source.dump();
    render(package, 1, packageLook(package));

    bake::BakeConfig refuse = tinyConfig();
    refuse.read.non_finite = vdb::NonFinitePolicy::Refuse;
    fs::remove(b.file);
    expectErrorNaming<vdb::VdbError>([&] { bakeInto(dir, seq, refuse); }, {frameName(1)});
    EXPECT_EQ(entries(dir.path()), std::vector<std::string>{"seq"});
}

TEST(HardCases, MissingGridNamesTheFile) {
    TempDir dir;
    const fs::path seq = dir / "seq";
    fs::create_directories(seq);
    writeFrame(seq, 1, constant(4, 1.0f), ramp(4));
    writeVdb(seq / frameName(2), {makeGrid("density", constant(4, 1.0f))});  // no temperature
    expectErrorNaming<vdb::VdbError>([&] { bakeInto(dir, seq, tinyConfig()); }, {frameName(2), "temperature"});
    EXPECT_EQ(entries(dir.path()), std::vector<std::string>{"seq"});
}

TEST(HardCases, PartnerGridWithADifferentTransformNamesTheFile) {
    TempDir dir;
    const fs::path seq = dir / "seq";
    fs::create_directories(seq);
    writeVdb(seq / frameName(1),
             {makeGrid("density", constant(4, 1.0f), 0.1), makeGrid("temperature", ramp(4), 0.2)});
    expectErrorNaming<vdb::VdbError>([&] { bakeInto(dir, seq, tinyConfig()); }, {frameName(1), "transform"});
    EXPECT_EQ(entries(dir.path()), std::vector<std::string>{"seq"});
}

TEST(HardCases, FramesOfDifferentSizes) {
    TempDir dir;
    const fs::path seq = dir / "seq";
    fs::create_directories(seq);
    writeFrame(seq, 1, constant(1, 3.0f), constant(1, 2.5f), 0.1);                  // one voxel
    writeFrame(seq, 2, constant(6, 1.0f), ramp(6), 0.1);                              // 216 voxels
    writeFrame(seq, 3, block(10, [](int, int, int) { return 0.5f; }, openvdb::Coord(-4)), ramp(10), 0.05);  // 1000, finer
    const Baked b = bakeInto(dir, seq, tinyConfig());
    const basis::BasisReader package = basis::BasisReader::open(b.file);
    ASSERT_EQ(package.description().frames.size(), 3u);
    for (int f = 1; f <= 3; ++f) {
        const Image image = render(package, f, packageLook(package));
        EXPECT_GT(image.maxAlpha(), 0.0f) << "frame " << f << " is seen by the sequence-wide camera";
    }
}

// Shared by the package tests below: one good tiny package, baked once.
class DamagedPackage : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        source_ = new TempDir;
        const fs::path seq = *source_ / "seq";
        fs::create_directories(seq);
        writeFrame(seq, 1, constant(6, 1.0f), ramp(6));
        writeFrame(seq, 2, constant(5, 1.5f), ramp(5));
        good_ = *source_ / "good.firelook";
        bake::bakePackage(seq.string(), good_, tinyConfig(), "hard-cases");
        std::ifstream in(good_, std::ios::binary);
        bytes_.assign(std::istreambuf_iterator<char>(in), {});
    }
    static void TearDownTestSuite() {
        delete source_;
        source_ = nullptr;
    }

    static fs::path writeCopy(const TempDir& dir, const std::string& name, const std::string& bytes) {
        const fs::path file = dir / name;
        std::ofstream(file, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        return file;
    }

    // Opens, loads and renders every frame; returns the first error's message ("" if none).
    static std::string openAndRenderAll(const fs::path& file) {
        try {
            const basis::BasisReader package = basis::BasisReader::open(file);
            for (const basis::FrameRecord& r : package.description().frames) render(package, r.frame, packageLook(package));
        } catch (const std::exception& e) {
            return e.what();
        }
        return "";
    }

    static TempDir* source_;
    static fs::path good_;
    static std::string bytes_;
};
TempDir* DamagedPackage::source_ = nullptr;
fs::path DamagedPackage::good_;
std::string DamagedPackage::bytes_;

TEST_F(DamagedPackage, GoodPackageRenders) { EXPECT_EQ(openAndRenderAll(good_), ""); }

TEST_F(DamagedPackage, TruncatedAnywhereFailsNamingTheFile) {
    TempDir dir;
    for (const std::size_t keep : {std::size_t{0}, std::size_t{5}, std::size_t{63}, std::size_t{64}, bytes_.size() / 3,
                                   bytes_.size() - 64, bytes_.size() - 1}) {
        const fs::path file = writeCopy(dir, "cut.firelook", bytes_.substr(0, keep));
        try {
            basis::BasisReader::open(file);
            ADD_FAILURE() << "a package cut to " << keep << " bytes opened";
        } catch (const package::PackageError& e) {
            EXPECT_NE(std::string(e.what()).find("cut.firelook"), std::string::npos) << e.what();
            EXPECT_TRUE(e.code() == package::ErrorCode::Truncated || e.code() == package::ErrorCode::NotAPackage)
                << keep << ": " << e.what();
        }
    }
}

// Every byte the format checksums (docs/package-format.md): the header [0, 64) (bytes [0, 56) by
// header_checksum, which is itself bytes [56, 64)), each section's stored bytes (its index entry's
// checksum; open() verifies the metadata, loadFrame the frame's sections) and the index (the header's
// index_checksum). A flip there must make open or a frame load fail, naming the file. The only bytes
// no checksum covers are the zero padding after each section up to the next multiple of 64, which
// readers never read: a flip there cannot be detected and must change nothing. Flipped: every 97th
// byte, every header byte, and the first and last byte of each section, of its padding and of the
// index. Measured: 8768 bytes, 7 sections; 184 flips, 169 of them checksummed, all detected, and 15
// in padding (0.5 s).
TEST_F(DamagedPackage, CorruptedBytesFailNamingTheFile) {
    TempDir dir;
    package::FileHeader header;
    ASSERT_GE(bytes_.size(), sizeof header);
    std::memcpy(&header, bytes_.data(), sizeof header);
    ASSERT_EQ(header.file_size, bytes_.size());
    ASSERT_EQ(header.index_offset + std::uint64_t{header.section_count} * sizeof(package::IndexEntry), bytes_.size());
    // What covers each byte: 'h' header, 'i' index, 's' section data, '.' padding (nothing).
    std::string cover(bytes_.size(), '.');
    std::fill(cover.begin(), cover.begin() + sizeof header, 'h');
    std::fill(cover.begin() + static_cast<std::ptrdiff_t>(header.index_offset), cover.end(), 'i');
    std::vector<std::size_t> at = {header.index_offset, bytes_.size() - 1};
    for (std::uint32_t n = 0; n < header.section_count; ++n) {
        package::IndexEntry entry;
        std::memcpy(&entry, bytes_.data() + header.index_offset + n * sizeof entry, sizeof entry);
        ASSERT_GT(entry.stored_size, 0u);
        ASSERT_LE(entry.offset + entry.stored_size, header.index_offset);
        std::fill_n(cover.begin() + static_cast<std::ptrdiff_t>(entry.offset), entry.stored_size, 's');
        const std::size_t end = entry.offset + entry.stored_size, padded = (end + 63) / 64 * 64;
        at.push_back(entry.offset);
        at.push_back(end - 1);
        if (padded > end) {
            at.push_back(end);
            at.push_back(padded - 1);
        }
    }
    for (std::size_t i = 0; i < sizeof header; ++i) at.push_back(i);
    for (std::size_t i = 0; i < bytes_.size(); i += 97) at.push_back(i);
    std::sort(at.begin(), at.end());
    at.erase(std::unique(at.begin(), at.end()), at.end());

    int detected = 0, padding = 0;
    for (const std::size_t i : at) {
        std::string damaged = bytes_;
        damaged[i] = static_cast<char>(damaged[i] ^ 0x5A);
        const fs::path file = writeCopy(dir, "flipped.firelook", damaged);
        const std::string error = openAndRenderAll(file);
        if (cover[i] == '.') {
            ++padding;
            EXPECT_EQ(bytes_[i], '\0') << "byte " << i << ": padding is written as zeros";
            EXPECT_EQ(error, "") << "byte " << i << " is padding, which readers never read";
        } else {
            ++detected;
            EXPECT_NE(error, "") << "byte " << i << " (" << cover[i] << ") flipped went unnoticed";
            EXPECT_NE(error.find("flipped.firelook"), std::string::npos) << "byte " << i << ": " << error;
        }
    }
    std::printf("[measured] %zu bytes, %u sections; flipped %zu: %d checksummed (all detected), %d padding\n",
                bytes_.size(), header.section_count, at.size(), detected, padding);
    EXPECT_GT(padding, 0) << "the padding case was exercised";
}

TEST_F(DamagedPackage, NewerVersionsAreRefusedOrReadAsDocumented) {
    TempDir dir;
    // Newer major version: refused before anything else is trusted.
    std::string newer = bytes_;
    newer[offsetof(package::FileHeader, version_major)] = 2;
    const fs::path major = writeCopy(dir, "major2.firelook", newer);
    try {
        basis::BasisReader::open(major);
        ADD_FAILURE() << "major version 2 opened";
    } catch (const package::PackageError& e) {
        EXPECT_EQ(e.code(), package::ErrorCode::NewerMajorVersion) << e.what();
        EXPECT_NE(std::string(e.what()).find("major2.firelook"), std::string::npos) << e.what();
    }
    // Newer minor version with a section this reader does not know: skipped when optional, refused
    // (naming the file) when required.
    const basis::BasisReader good = basis::BasisReader::open(good_);
    for (const bool required : {false, true}) {
        const fs::path file = dir / (required ? "minor_required.firelook" : "minor_optional.firelook");
        {
            package::ContainerWriter writer(file, package::WriterOptions{3, package::kFormatMinor + 1});
            for (const basis::FrameRecord& r : good.description().frames)
                basis::writeFrameFactors(writer, good.description(), good.loadFrame(r.frame));
            const std::string extra = "from the future";
            writer.addSection(package::makeFourCC('N', 'E', 'W', '1'), package::kNoFrame, std::as_bytes(std::span(extra)),
                              package::Codec::Zstd, required);
            writer.addMetadata(good.metadataJson());
            writer.commit();
        }
        const std::string error = openAndRenderAll(file);
        if (required) {
            EXPECT_NE(error.find(file.filename().string()), std::string::npos) << error;
            EXPECT_NE(error.find("required"), std::string::npos) << error;
        } else {
            EXPECT_EQ(error, "") << "an optional unknown section is skipped";
        }
    }
}

TEST_F(DamagedPackage, InterruptedBakeLeavesNothingAndItsTemporaryFileIsRefused) {
    TempDir dir;
    const fs::path seq = *source_ / "seq";
    // Cancelled from the progress callback (what Ctrl-C does): no package, no temporary file.
    for (const int cancel_at : {1, 2, 4}) {
        int calls = 0;
        const auto progress = [&](double, const std::string&) { return ++calls < cancel_at; };
        EXPECT_THROW(bake::bakePackage(seq.string(), dir / "out.firelook", tinyConfig(), "hard-cases", progress),
                     std::runtime_error);
        EXPECT_TRUE(entries(dir.path()).empty()) << "cancel at " << cancel_at << " left " << entries(dir.path())[0];
    }
    // A process killed outright leaves the writer's temporary file: it is not a package.
    const basis::BasisReader good = basis::BasisReader::open(good_);
    fs::path leftover = dir / "killed.firelook.tmp";
    {
        package::ContainerWriter writer(dir / "killed.firelook");
        basis::writeFrameFactors(writer, good.description(), good.loadFrame(1));
        fs::copy_file(writer.temporaryPath(), leftover);
    }  // destroyed without commit: as if the bake died here
    EXPECT_FALSE(fs::exists(dir / "killed.firelook"));
    const std::string error = openAndRenderAll(leftover);
    EXPECT_NE(error.find("killed.firelook.tmp"), std::string::npos) << error;
    expectErrorNaming<package::PackageError>([&] { basis::BasisReader::open(dir / "killed.firelook"); },
                                             {"killed.firelook"});
}

// The camera at the centre (0.45, 0.45, 0.45) of a 10^3 block of density 1 and voxel size 0.1
// (flat on [0, 0.9], ramping to 0 over one voxel beyond), looking down -Z with a 70 degree field
// of view. Frame 1 has temperatures rising along x (smoke and flame); frame 2 a uniform T = 1.5
// (the temperature grid's background too), i.e. a homogeneous box. There every ray leaves through
// the z = 0 face, crossing its ramp (z from 0 to -0.1) at |x - 0.45|, |y - 0.45| <= 0.55 tan(35
// deg) = 0.385, inside the flat part of the other axes, so its optical depth is exactly
// kappa rho 0.5 / |dir.z| (0.5 from the centre to the face: 0.45 flat plus the ramp's half voxel),
// and a pixel's alpha is the mean of 1 - exp(-that) over its 3 x 3 footprint rays. The look's T_c
// is the first alpha threshold the bake stored, so no interpolation between threshold layers enters.
// Tolerance: the march's midpoint error at the ramp's two kinks, at most
// rho |dir.z| edge / 128 = 7.8e-4 of density path each (steps of 1/4 voxel, see
// tests/bake/hard_cases_test.cpp), times kappa (1 - alpha), plus 2e-4 for the optical depths the
// package stores as halfs (basis_package.cpp): 1.3e-3 at the centre pixels (kappa 2.35, alpha 0.69).
// Measured: worst alpha error 4.5e-5. A march that also counted the density behind the camera would
// be off by ~0.2, one that skipped its first step (1/4 voxel) by ~1.7e-2.
TEST(HardCases, CameraInsideTheVolume) {
    TempDir dir;
    const fs::path seq = dir / "seq";
    fs::create_directories(seq);
    constexpr float kUniform = 1.5f;
    writeFrame(seq, 1, constant(10, 1.0f), ramp(10));
    writeFrame(seq, 2, constant(10, 1.0f), constant(10, kUniform), 0.1, kUniform);
    bake::BakeConfig config = tinyConfig();
    config.scene.camera = std::array<double, 7>{0.45, 0.45, 0.45, 0.45, 0.45, 0.0, 70.0};
    const Baked b = bakeInto(dir, seq, config);
    const basis::BasisReader package = basis::BasisReader::open(b.file);
    const Image image = render(package, 1, packageLook(package));
    EXPECT_GT(image.minAlpha(), 0.0f) << "every ray starts inside the density";
    EXPECT_LT(image.maxAlpha(), 1.0f);

    const basis::BakeDescription& d = package.description();
    Look look = packageLook(package);
    look.temperature_threshold = d.alpha_thresholds.front();
    const Image uniform = render(package, 2, look);
    EXPECT_GT(uniform.minAlpha(), 0.0f);
    EXPECT_LT(uniform.maxAlpha(), 1.0f);
    const double kappa = extinctionPerDensity(
        kUniform, ExtinctionParams{look.temperature_threshold, look.smoke_extinction, look.flame_extinction}, d.bins);
    const render::Camera camera = render::Camera::lookAt({0.45, 0.45, 0.45}, {0.45, 0.45, 0.0}, {0.0, 1.0, 0.0},
                                                         70.0 * std::numbers::pi / 180.0, d.width, d.height);
    const int n = static_cast<int>(std::lround(std::sqrt(d.footprint_samples)));
    ASSERT_EQ(n * n, d.footprint_samples);
    const double kink = 1.0 * 0.1 / 128.0;
    double worst = 0.0;
    for (int p = 0; p < d.width * d.height; ++p) {
        double expected = 0.0;
        for (int sample = 0; sample < n * n; ++sample) {
            const render::Ray ray =
                camera.generateRay(p % d.width, p / d.width, (sample % n + 0.5) / n, (sample / n + 0.5) / n);
            expected += (1.0 - std::exp(-kappa * 0.5 / std::abs(ray.direction.z))) / (n * n);
        }
        const double got = uniform.rgba[static_cast<std::size_t>(p) * 4 + 3];
        worst = std::max(worst, std::abs(got - expected));
        EXPECT_NEAR(got, expected, kappa * 2.0 * kink * (1.0 - expected) + 2e-4) << "pixel " << p;
    }
    std::printf("[measured] camera inside, uniform T %.1f (kappa %.3f): worst alpha error %.2e\n", kUniform, kappa,
                worst);
}

TEST(HardCases, CameraLookingAway) {
    TempDir dir;
    const fs::path seq = dir / "seq";
    fs::create_directories(seq);
    writeFrame(seq, 1, constant(6, 1.0f), ramp(6));
    bake::BakeConfig config = tinyConfig();
    config.scene.camera = std::array<double, 7>{0.25, 0.25, 2.0, 0.25, 0.25, 5.0, 40.0};
    const Baked b = bakeInto(dir, seq, config);
    const basis::BasisReader package = basis::BasisReader::open(b.file);
    const Image image = render(package, 1, packageLook(package));
    EXPECT_EQ(image.maxAlpha(), 0.0f);
    EXPECT_EQ(image.maxRadiance(), 0.0f);
}

}  // namespace
}  // namespace firelook
