// The figures of README "Look fitting" (scripts/bench/fit.sh).
//   bench_fit looks PACKAGE FRAME [COUNT=20] [SEED=1]
//     COUNT random looks inside the package's baked ranges, each rendered by the runtime and fitted
//     back from its image alone: image error (relative RMSE, max alpha error), parameter errors
//     and fit seconds per look, then medians and worst.
//   bench_fit blackbody SEQUENCE PACKAGE FRAME SPP OUT.exr [KELVIN_PER_UNIT=1000] [KELVIN_AT_0=300]
//     (also OUT.png)
//   bench_fit montage OUT.png LAST_SCALE IMAGE...
//     the images side by side over black, the last scaled by LAST_SCALE (a difference made visible).
//     A target from outside the model: the reference path tracer with the package's default
//     extinction and light, but an emission law L_e(T) = Planck's radiance at
//     K = KELVIN_AT_0 + KELVIN_PER_UNIT * T (linear sRGB, colour and brightness), represented on 128
//     narrow bins instead of the package's, scaled to luminance 12 at T = 2.5.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory_resource>
#include <random>
#include <string>
#include <vector>

#include "../support/bench_timing.h"
#include "basis/basis_package.h"
#include "basis/look_renderer.h"
#include "fit/look_fit.h"
#include "image/image_io.h"
#include "look/blackbody.h"
#include "look/emission_fit.h"
#include "look/look.h"
#include "reference/frame_medium.h"
#include "bake/scene_setup.h"
#include "render/reference_tracer.h"
#include "vdb/vdb_sequence.h"
#include "world/package_camera.h"

namespace {

using namespace firelook;

double uniformIn(std::mt19937& rng, const std::vector<double>& axis) {
    return std::uniform_real_distribution<double>(axis.front(), axis.back())(rng);
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : (v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]));
}
double worst(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }

int benchLooks(const std::string& path, int frame_number, int count, unsigned seed) {
    const basis::BasisReader package = basis::BasisReader::open(path);
    const basis::BakeDescription& d = package.description();
    const basis::ResidentFrame frame = package.loadResidentFrame(frame_number, std::pmr::get_default_resource());
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<double> rmse, alpha, seconds, d_tc, d_ks, d_kf;
    std::printf("look  rel.RMSE  max|da|   T_c true/fit    k_s true/fit    k_f true/fit   seconds\n");
    for (int i = 0; i < count; ++i) {
        Look truth;
        truth.temperature_threshold = uniformIn(rng, d.axes.temperature_threshold);
        truth.smoke_extinction = uniformIn(rng, d.axes.smoke_extinction);
        truth.flame_extinction = uniformIn(rng, d.axes.flame_extinction);
        truth.albedo = d.albedo;
        // A ramp rising with temperature, its colour drawn per look, and a random light.
        EmissionBins e;
        const double top = 4.0 + 16.0 * u(rng), green = 0.2 + 0.5 * u(rng), blue = 0.05 + 0.25 * u(rng);
        const double power = 1.0 + 2.0 * u(rng);
        for (int b = 0; b < d.bins.count; ++b) {
            const double r = top * std::pow((b + 0.5) / d.bins.count, power);
            e.emissivity.push_back(Rgb(float(r), float(r * green), float(r * blue)));
        }
        truth.emission = e;
        for (size_t l = 0; l < d.light_directions.size(); ++l)
            truth.light_irradiance.push_back(Rgb(float(0.3 + u(rng)), float(0.3 + u(rng)), float(0.3 + u(rng))));
        fit::FrameTarget target;
        target.frame = frame_number;
        target.rgba.resize(static_cast<size_t>(d.pixelCount()) * 4);
        basis::renderLookImage(d, frame, truth, target.rgba);
        const basis::ResidentFrame* frames[] = {&frame};
        const auto start = std::chrono::steady_clock::now();
        const fit::FitResult r = fit::fitLook(d, frames, std::span(&target, 1));
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        rmse.push_back(r.relative_rmse);
        alpha.push_back(r.alpha_max_error);
        seconds.push_back(s);
        d_tc.push_back(std::abs(r.look.temperature_threshold - truth.temperature_threshold));
        d_ks.push_back(std::abs(r.look.smoke_extinction - truth.smoke_extinction));
        d_kf.push_back(std::abs(r.look.flame_extinction - truth.flame_extinction));
        std::printf("%4d  %7.4f%%  %7.4f   %6.3f/%6.3f   %6.3f/%6.3f   %6.3f/%6.3f   %6.3f\n", i,
                    100 * r.relative_rmse, r.alpha_max_error, truth.temperature_threshold,
                    r.look.temperature_threshold, truth.smoke_extinction, r.look.smoke_extinction,
                    truth.flame_extinction, r.look.flame_extinction, s);
        std::fflush(stdout);
    }
    std::printf("%d looks, frame %d, %dx%d, rank %d: relative RMSE median %.4f%% worst %.4f%%; max alpha error "
                "median %.4f worst %.4f\n",
                count, frame_number, d.width, d.height, frame.rank, 100 * median(rmse), 100 * worst(rmse),
                median(alpha), worst(alpha));
    std::printf("parameter error |fit - truth|: T_c median %.3f worst %.3f; k_s median %.3f worst %.3f; k_f median "
                "%.3f worst %.3f\n",
                median(d_tc), worst(d_tc), median(d_ks), worst(d_ks), median(d_kf), worst(d_kf));
    std::printf("fit seconds: median %.3f, worst %.3f\n", median(seconds), worst(seconds));
    return 0;
}

int benchBlackbody(const std::string& sequence_path, const std::string& package_path, int frame_number, int spp,
                   const std::string& out, double kelvin_per_unit, double kelvin_at_0) {
    const basis::BasisReader package = basis::BasisReader::open(package_path);
    const basis::BakeDescription& d = package.description();
    const auto baked = world::readPackageCamera(package.metadataJson(), package_path);
    if (!baked) throw std::runtime_error(package_path + ": records no camera");
    render::CameraParameters cp;
    cp.world_from_camera = baked->world_from_camera;
    cp.yfov_radians = baked->yfov_radians;
    cp.width = baked->width;
    cp.height = baked->height;
    const render::Camera camera(cp);
    const Look base = parseLook(d.default_look_json, package_path + " (default look)");
    LookModel model = makeLookModel(base, d.bins, d.rbf_width, d.light_directions);

    EmissionBasis fine{TemperatureBins{d.bins.t_lo, d.bins.t_hi, 128}, kDefaultRbfWidth, true};
    const auto planck = [&](double t) {
        const glm::dvec3 rgb = xyzToLinearSrgb(blackbodyXyz(kelvin_at_0 + kelvin_per_unit * t));
        return glm::max(rgb, glm::dvec3(0.0));
    };
    const double scale = 12.0 / std::max(1e-300, blackbodyXyz(kelvin_at_0 + kelvin_per_unit * 2.5).y);
    std::vector<Rgb> per_bin;
    for (int i = 0; i < fine.bins.count; ++i) per_bin.push_back(Rgb(planck(fine.bins.center(i)) * scale));
    model.emission.basis = fine;
    model.emission.coefficients = fitEmissionCoefficients(fine, per_bin);

    const render::Medium medium = reference::mediumFromFrame(
        vdb::VdbSequence::open(sequence_path, vdb::ReadOptions{}).load(frame_number));
    render::ReferenceSettings settings;
    settings.samples_per_pixel = spp;
    const render::ReferenceResult r = render::renderReference(medium, model, camera, settings);
    image::ImageRGBA img(r.image.width, r.image.height);
    img.pixels = r.image.rgba;
    image::writeImage(out, img);
    // The same as PNG beside it, for the README's picture.
    image::writeImage(std::filesystem::path(out).replace_extension(".png"), img);
    std::printf("wrote %s (and .png): blackbody emission K = %g + %g T, %d spp, %.1f s, estimated relative RMSE %.4f\n",
                out.c_str(), kelvin_at_0, kelvin_per_unit, spp, r.seconds, r.estimated_relative_rmse);
    return 0;
}

// Images side by side over black (one PNG for the README), the last scaled by `last_scale` to make
// a difference visible; all must have the same height.
int montage(const std::string& out, double last_scale, const std::vector<std::string>& inputs) {
    std::vector<image::ImageRGBA> images;
    int width = 0;
    for (const std::string& path : inputs) {
        images.push_back(image::readImage(path));
        if (images.back().height != images.front().height) throw std::runtime_error(path + ": another height");
        width += images.back().width;
    }
    image::ImageRGBA m(width, images.front().height);
    int x0 = 0;
    for (size_t k = 0; k < images.size(); ++k) {
        const image::ImageRGBA& in = images[k];
        const float scale = k + 1 == images.size() ? static_cast<float>(last_scale) : 1.0f;
        for (int y = 0; y < in.height; ++y)
            for (int x = 0; x < in.width; ++x) {
                const float* p = in.pixels.data() + 4 * (static_cast<size_t>(y) * in.width + x);
                float* q = m.pixels.data() + 4 * (static_cast<size_t>(y) * width + x0 + x);
                for (int c = 0; c < 3; ++c) q[c] = p[c] * scale;  // premultiplied: over black as it is
                q[3] = 1.0f;
            }
        x0 += in.width;
    }
    image::writeImage(out, m);
    std::printf("wrote %s\n", out.c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        const std::string mode = argc > 1 ? argv[1] : "";
        if (mode == "looks" && argc >= 4)
            return benchLooks(argv[2], std::atoi(argv[3]), argc > 4 ? std::atoi(argv[4]) : 20,
                              argc > 5 ? static_cast<unsigned>(std::atoi(argv[5])) : 1u);
        if (mode == "blackbody" && argc >= 7)
            return benchBlackbody(argv[2], argv[3], std::atoi(argv[4]), std::atoi(argv[5]), argv[6],
                                  argc > 7 ? std::atof(argv[7]) : 1000.0, argc > 8 ? std::atof(argv[8]) : 300.0);
        if (mode == "montage" && argc >= 5)
            return montage(argv[2], std::atof(argv[3]), std::vector<std::string>(argv + 4, argv + argc));
        std::fprintf(stderr,
                     "usage: bench_fit looks PACKAGE FRAME [COUNT] [SEED]\n"
                     "       bench_fit blackbody SEQUENCE PACKAGE FRAME SPP OUT.exr [KELVIN_PER_UNIT] [KELVIN_AT_0]\n"
                     "       bench_fit montage OUT.png LAST_SCALE IMAGE...\n");
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_fit: error: %s\n", e.what());
        return 1;
    }
}
