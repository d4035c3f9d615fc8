// bench_relight: the error of relighting from a direction chosen at run time (basis/relight.h)
// against the reference path tracer, for scripts/bench/relight.sh (README, "Light from any
// direction"). Modes:
//   bench_relight directions N SEED           N directions uniform on the sphere ("name x y z" lines)
//   bench_relight baked PACKAGE                the six-way lights' own directions (baked_NAME lines)
//   bench_relight look PACKAGE OUT.json        the package's default look with no emission and every
//                                             light off: the image is the relit light alone
//   bench_relight judge PACKAGE FRAME LOOK DIR for each line of DIR/directions.txt, the package relit
//                                             with several weightings against the mean of
//                                             DIR/ref_NAME_s1.exr and _s2.exr (the reference's noise,
//                                             their difference / 2, removed in quadrature)
// Weightings: w_i = max(0, d.t_i)^p normalised for p = 1, 2, 4; the nearest baked light alone; and
// the best any six non-negative weights can do for that direction (non-negative least squares on
// the reference itself: a bound, not a method).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "basis/basis_package.h"
#include "basis/look_renderer.h"
#include "basis/relight.h"
#include "image/image_io.h"
#include "look/detail/non_negative_least_squares.h"
#include "look/look.h"
#include "render/render_image.h"

using namespace firelook;

namespace {

constexpr double kPi = 3.14159265358979323846;

int directions(int n, uint64_t seed) {
    // Uniform on the sphere: z uniform in [-1, 1], azimuth uniform (from raw 64-bit draws, so the
    // same on every standard library).
    std::mt19937_64 random(seed);
    const auto uniform = [&] { return static_cast<double>(random() >> 11) * 0x1.0p-53; };
    for (int i = 0; i < n; ++i) {
        const double z = 2.0 * uniform() - 1.0, phi = 2.0 * kPi * uniform();
        const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
        std::printf("random_%02d %.17g %.17g %.17g\n", i, r * std::cos(phi), r * std::sin(phi), z);
    }
    return 0;
}

std::span<const glm::dvec3, basis::kSixWayLightCount> sixWay(const basis::BakeDescription& d) {
    if (d.six_way_first_light < 0) throw std::runtime_error("the package has no six-way lights");
    return std::span<const glm::dvec3, basis::kSixWayLightCount>(d.light_directions.data() + d.six_way_first_light,
                                                                 basis::kSixWayLightCount);
}

int bakedDirections(const std::string& package) {
    const basis::BasisReader p = basis::BasisReader::open(package);
    const auto six = sixWay(p.description());
    for (int i = 0; i < basis::kSixWayLightCount; ++i)
        std::printf("baked_%s %.17g %.17g %.17g\n", std::string(basis::kSixWayLightNames[i]).c_str(), six[i].x,
                    six[i].y, six[i].z);
    return 0;
}

Look darkLook(const basis::BakeDescription& d) {
    Look look = parseLook(d.default_look_json, "default look");
    look.emission = EmissionBins{std::vector<Rgb>(static_cast<size_t>(d.bins.count), Rgb(0.0f))};
    std::fill(look.light_irradiance.begin(), look.light_irradiance.end(), Rgb(0.0f));
    return look;
}

render::RenderImage renderWith(const basis::BakeDescription& d, const basis::ResidentFrame& frame, Look look,
                               std::span<const double, basis::kSixWayLightCount> weights) {
    for (int i = 0; i < basis::kSixWayLightCount; ++i)
        look.light_irradiance[static_cast<size_t>(d.six_way_first_light + i)] = Rgb(static_cast<float>(weights[i]));
    render::RenderImage image{d.width, d.height, std::vector<float>(static_cast<size_t>(d.pixelCount()) * 4)};
    basis::renderLookImage(d, frame, look, image.rgba);
    return image;
}

render::RenderImage readRender(const std::string& path) {
    const image::ImageRGBA i = image::readImage(path);
    return {i.width, i.height, i.pixels};
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

int judge(const std::string& package, int frame_number, const std::string& look_path, const std::string& dir) {
    const basis::BasisReader p = basis::BasisReader::open(package);
    const basis::BakeDescription& d = p.description();
    const auto six = sixWay(d);
    const basis::ResidentFrame frame = p.loadResidentFrame(frame_number, std::pmr::get_default_resource());
    const Look look = loadLook(look_path);
    // The six lights' images at unit irradiance, for the non-negative fit.
    std::vector<render::RenderImage> single;
    for (int i = 0; i < basis::kSixWayLightCount; ++i) {
        std::array<double, basis::kSixWayLightCount> w{};
        w[i] = 1.0;
        single.push_back(renderWith(d, frame, look, w));
    }
    const std::vector<std::pair<std::string, double>> exponents = {{"cos^1", 1.0}, {"cos^2", 2.0}, {"cos^4", 4.0}};
    const std::vector<std::string> methods = {"cos^1", "cos^2", "cos^4", "nearest", "nnls-bound"};
    std::map<std::string, std::vector<double>> raw, corrected;
    std::vector<double> noises;
    std::ifstream list(dir + "/directions.txt");
    std::string line;
    std::printf("%-14s %8s", "direction", "noise");
    for (const std::string& m : methods) std::printf(" %11s", m.c_str());
    std::printf("   (relative RMSE, %%, noise removed)\n");
    while (std::getline(list, line)) {
        std::istringstream fields(line);
        std::string name;
        glm::dvec3 direction;
        if (!(fields >> name >> direction.x >> direction.y >> direction.z)) continue;
        const render::RenderImage a = readRender(dir + "/ref_" + name + "_s1.exr");
        const render::RenderImage b = readRender(dir + "/ref_" + name + "_s2.exr");
        render::RenderImage reference = a;
        for (size_t k = 0; k < reference.rgba.size(); ++k) reference.rgba[k] = 0.5f * (a.rgba[k] + b.rgba[k]);
        // Each seed's error is |a - b| / sqrt(2), their mean's half |a - b|, which is |a - mean|.
        const double noise = render::relativeRmse(a, reference);
        noises.push_back(noise);
        std::map<std::string, double> errors;
        for (const auto& [m, exponent] : exponents)
            errors[m] = render::relativeRmse(renderWith(d, frame, look, basis::relightWeights(six, direction, exponent)),
                                             reference);
        std::array<double, basis::kSixWayLightCount> nearest{};
        nearest[static_cast<size_t>(std::max_element(six.begin(), six.end(),
                                                     [&](const glm::dvec3& x, const glm::dvec3& y) {
                                                         return glm::dot(x, direction) < glm::dot(y, direction);
                                                     }) -
                                    six.begin())] = 1.0;
        errors["nearest"] = render::relativeRmse(renderWith(d, frame, look, nearest), reference);
        // min || sum_i w_i I_i - R ||, w >= 0, over every pixel's RGB.
        const int pixels = d.pixelCount();
        detail::DenseMatrix m(3 * pixels, basis::kSixWayLightCount);
        std::vector<double> rhs(static_cast<size_t>(3 * pixels));
        for (int q = 0; q < pixels; ++q)
            for (int c = 0; c < 3; ++c) {
                for (int i = 0; i < basis::kSixWayLightCount; ++i) m(3 * q + c, i) = single[i].rgba[4 * q + c];
                rhs[static_cast<size_t>(3 * q + c)] = reference.rgba[4 * q + c];
            }
        const std::vector<double> fit = detail::nonNegativeLeastSquares(m, rhs);
        std::array<double, basis::kSixWayLightCount> fitted{};
        std::copy(fit.begin(), fit.end(), fitted.begin());
        errors["nnls-bound"] = render::relativeRmse(renderWith(d, frame, look, fitted), reference);
        std::printf("%-14s %7.2f%%", name.c_str(), 100.0 * noise);
        for (const std::string& method : methods) {
            const double e = errors[method];
            const double c = std::sqrt(std::max(0.0, e * e - noise * noise));
            if (name.rfind("random", 0) == 0) {
                raw[method].push_back(e);
                corrected[method].push_back(c);
            }
            std::printf(" %5.2f (%4.2f)", 100.0 * c, 100.0 * e);
        }
        std::printf("\n");
    }
    if (raw.empty()) return 0;
    std::printf("random directions: %zu; reference noise median %.2f%%\n", raw["cos^1"].size(), 100.0 * median(noises));
    for (const std::string& m : methods)
        std::printf("%-11s noise removed: median %.2f%%, worst %.2f%%; raw: median %.2f%%, worst %.2f%%\n", m.c_str(),
                    100.0 * median(corrected[m]), 100.0 * *std::max_element(corrected[m].begin(), corrected[m].end()),
                    100.0 * median(raw[m]), 100.0 * *std::max_element(raw[m].begin(), raw[m].end()));
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        const std::string mode = argc > 1 ? argv[1] : "";
        if (mode == "directions" && argc == 4) return directions(std::stoi(argv[2]), std::stoull(argv[3]));
        if (mode == "baked" && argc == 3) return bakedDirections(argv[2]);
        if (mode == "look" && argc == 4) {
            const basis::BasisReader p = basis::BasisReader::open(argv[2]);
            saveLook(argv[3], darkLook(p.description()));
            return 0;
        }
        if (mode == "judge" && argc == 6) return judge(argv[2], std::stoi(argv[3]), argv[4], argv[5]);
        std::fprintf(stderr,
                     "usage: bench_relight directions N SEED | baked PACKAGE | look PACKAGE OUT.json | "
                     "judge PACKAGE FRAME LOOK.json DIR\n");
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_relight: %s\n", e.what());
        return 1;
    }
}
