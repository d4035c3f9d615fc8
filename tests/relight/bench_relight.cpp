// bench_relight: the error of relighting from a direction chosen at run time (basis/relight.h)
// against the reference path tracer, for scripts/bench/relight.sh (README, "Light from any
// direction"). Modes:
//   bench_relight directions N SEED           N directions uniform on the sphere ("name x y z" lines)
//   bench_relight baked PACKAGE                the six-way lights' own directions (baked_NAME lines)
//   bench_relight look PACKAGE OUT.json        the package's default look with no emission and every
//                                             light off: the image is the relit light alone
//   bench_relight judge PACKAGE FRAME LOOK DIRECTIONS PREFIX
//                                             for each line of DIRECTIONS, the package (six-way or
//                                             sphere lights) relit with several weightings against
//                                             the mean of PREFIX+NAME_s1.exr and _s2.exr (the
//                                             reference's noise, their difference / 2, removed in
//                                             quadrature)
// Weightings: "used" (the runtime's: relight.h); w_i = max(0, d.t_i)^p normalised (p = 1, 4 for
// six-way; 8, 16, 32 for a sphere); for a sphere, the least-squares fit of real spherical harmonics
// through band L to the baked directions, evaluated at d (sh-lL); the nearest baked light alone; and
// the best any non-negative weights can do for that direction (non-negative least squares on the
// reference itself: a bound, not a method).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "basis/basis_package.h"
#include "basis/look_renderer.h"
#include "basis/relight.h"
#include "image/image_io.h"
#include "look/detail/dense_linear_algebra.h"
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

// The image of relight light `i` alone at unit irradiance.
render::RenderImage lightAlone(const basis::BakeDescription& d, const basis::ResidentFrame& frame, Look look,
                               int i) {
    look.light_irradiance[static_cast<size_t>(d.relightFirstLight() + i)] = Rgb(1.0f);
    render::RenderImage image{d.width, d.height, std::vector<float>(static_cast<size_t>(d.pixelCount()) * 4)};
    basis::renderLookImage(d, frame, look, image.rgba);
    return image;
}

// sum_i w_i single_i: the image is linear in the lights' irradiance, so this is the package's image
// under those weights (negative ones too, which a look refuses).
render::RenderImage combine(const std::vector<render::RenderImage>& single, std::span<const double> w) {
    render::RenderImage out = single.front();
    for (size_t k = 0; k < out.rgba.size(); ++k) {
        double v = 0.0;
        for (size_t i = 0; i < single.size(); ++i) v += w[i] * single[i].rgba[k];
        out.rgba[k] = static_cast<float>(v);
    }
    return out;
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

// Real spherical harmonics through band `bands` - 1 at unit direction d (unnormalised per band: a
// least-squares fit does not depend on the scale of each basis function).
std::vector<double> sphericalHarmonics(const glm::dvec3& d, int bands) {
    const double z = std::clamp(d.z, -1.0, 1.0), phi = std::atan2(d.y, d.x);
    const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
    std::vector<double> out;
    for (int l = 0; l < bands; ++l)
        for (int m = -l; m <= l; ++m) {
            const int a = std::abs(m);
            // Associated Legendre P_l^a(z) by the standard recurrence.
            double pmm = 1.0;
            for (int k = 1; k <= a; ++k) pmm *= -(2.0 * k - 1.0) * s;
            double p = pmm;
            if (l > a) {
                double pm1 = z * (2.0 * a + 1.0) * pmm, pm2 = pmm;
                p = pm1;
                for (int ll = a + 2; ll <= l; ++ll) {
                    p = ((2.0 * ll - 1.0) * z * pm1 - (ll + a - 1.0) * pm2) / (ll - a);
                    pm2 = pm1, pm1 = p;
                }
            }
            double norm = 1.0;  // sqrt((l - a)! / (l + a)!), keeping the bands comparable
            for (int k = l - a + 1; k <= l + a; ++k) norm /= std::sqrt(static_cast<double>(k));
            out.push_back(norm * p * (m > 0 ? std::cos(m * phi) : m < 0 ? std::sin(a * phi) : 1.0));
        }
    return out;
}

// Weights of the N baked directions that give the least-squares SH fit (bands) evaluated at d:
// w = Y (Y^T Y)^-1 y(d), Y the N x K matrix of the harmonics at the baked directions.
std::vector<double> harmonicWeights(const std::vector<glm::dvec3>& baked, const glm::dvec3& d, int bands) {
    const int n = static_cast<int>(baked.size()), k = bands * bands;
    std::vector<std::vector<double>> y;
    for (const glm::dvec3& t : baked) y.push_back(sphericalHarmonics(t, bands));
    detail::DenseMatrix gram(k, k);
    for (int a = 0; a < k; ++a)
        for (int b = 0; b < k; ++b)
            for (int i = 0; i < n; ++i) gram(a, b) += y[i][a] * y[i][b];
    const std::vector<double> z = detail::solveLeastSquares(gram, sphericalHarmonics(d, bands));
    std::vector<double> w(static_cast<size_t>(n), 0.0);
    for (int i = 0; i < n; ++i)
        for (int a = 0; a < k; ++a) w[i] += y[i][a] * z[a];
    return w;
}

std::vector<double> cosinePower(const std::vector<glm::dvec3>& baked, const glm::dvec3& d, double p) {
    std::vector<double> w;
    double sum = 0.0;
    for (const glm::dvec3& t : baked) sum += w.emplace_back(std::pow(std::max(0.0, glm::dot(d, t)), p));
    for (double& x : w) x /= sum;
    return w;
}

int judge(const std::string& package, int frame_number, const std::string& look_path,
          const std::string& list_path, const std::string& prefix) {
    const basis::BasisReader p = basis::BasisReader::open(package);
    const basis::BakeDescription& d = p.description();
    const int first = d.relightFirstLight(), count = d.relightLightCount();
    if (first < 0) throw std::runtime_error("the package has no six-way or sphere lights");
    const basis::ResidentFrame frame = p.loadResidentFrame(frame_number, std::pmr::get_default_resource());
    const Look look = loadLook(look_path);
    std::vector<glm::dvec3> baked;
    for (int i = 0; i < count; ++i)
        baked.push_back(glm::normalize(d.light_directions[static_cast<size_t>(first + i)]));
    std::vector<render::RenderImage> single;
    for (int i = 0; i < count; ++i) single.push_back(lightAlone(d, frame, look, i));
    // The weightings: "used" is the runtime's (relight.h); the others are measured beside it.
    using Weighting = std::function<std::vector<double>(const glm::dvec3&)>;
    std::vector<std::pair<std::string, Weighting>> weightings = {
        {"used", [&](const glm::dvec3& x) { return basis::packageRelightWeights(d, x, package); }}};
    if (d.six_way_first_light >= 0) {
        for (double e : {1.0, 4.0})
            weightings.emplace_back("cos^" + std::to_string(static_cast<int>(e)),
                                    [&, e](const glm::dvec3& x) { return cosinePower(baked, x, e); });
    } else {
        for (double e : {8.0, 16.0, 32.0})
            weightings.emplace_back("cos^" + std::to_string(static_cast<int>(e)),
                                    [&, e](const glm::dvec3& x) { return cosinePower(baked, x, e); });
        for (int bands = 2; bands * bands <= count && bands <= 6; ++bands)
            weightings.emplace_back("sh-l" + std::to_string(bands - 1), [&, bands](const glm::dvec3& x) {
                return harmonicWeights(baked, x, bands);
            });
    }
    weightings.emplace_back("nearest", [&](const glm::dvec3& x) {
        std::vector<double> w(static_cast<size_t>(count), 0.0);
        w[static_cast<size_t>(std::max_element(baked.begin(), baked.end(),
                                               [&](const glm::dvec3& a, const glm::dvec3& b) {
                                                   return glm::dot(a, x) < glm::dot(b, x);
                                               }) -
                              baked.begin())] = 1.0;
        return w;
    });
    std::vector<std::string> methods;
    for (const auto& [name, f] : weightings) methods.push_back(name);
    methods.push_back("nnls-bound");
    std::map<std::string, std::vector<double>> raw, corrected;
    std::vector<double> noises;
    std::ifstream list(list_path);
    std::string line;
    std::printf("%-14s %8s", "direction", "noise");
    for (const std::string& m : methods) std::printf(" %13s", m.c_str());
    std::printf("   (relative RMSE, %%, noise removed (raw))\n");
    while (std::getline(list, line)) {
        std::istringstream fields(line);
        std::string name;
        glm::dvec3 direction;
        if (!(fields >> name >> direction.x >> direction.y >> direction.z)) continue;
        const render::RenderImage a = readRender(prefix + name + "_s1.exr");
        const render::RenderImage b = readRender(prefix + name + "_s2.exr");
        render::RenderImage reference = a;
        for (size_t k = 0; k < reference.rgba.size(); ++k) reference.rgba[k] = 0.5f * (a.rgba[k] + b.rgba[k]);
        // Each seed's error is |a - b| / sqrt(2), their mean's half |a - b|, which is |a - mean|.
        const double noise = render::relativeRmse(a, reference);
        noises.push_back(noise);
        std::map<std::string, double> errors;
        const glm::dvec3 unit = glm::normalize(direction);
        for (const auto& [m, weights] : weightings)
            errors[m] = render::relativeRmse(combine(single, weights(unit)), reference);
        // min || sum_i w_i I_i - R ||, w >= 0, over every pixel's RGB.
        const int pixels = d.pixelCount();
        detail::DenseMatrix m(3 * pixels, count);
        std::vector<double> rhs(static_cast<size_t>(3 * pixels));
        for (int q = 0; q < pixels; ++q)
            for (int c = 0; c < 3; ++c) {
                for (int i = 0; i < count; ++i) m(3 * q + c, i) = single[i].rgba[4 * q + c];
                rhs[static_cast<size_t>(3 * q + c)] = reference.rgba[4 * q + c];
            }
        errors["nnls-bound"] =
            render::relativeRmse(combine(single, detail::nonNegativeLeastSquares(m, rhs)), reference);
        std::printf("%-14s %7.2f%%", name.c_str(), 100.0 * noise);
        for (const std::string& method : methods) {
            const double e = errors[method];
            const double c = std::sqrt(std::max(0.0, e * e - noise * noise));
            if (name.rfind("random", 0) == 0) {
                raw[method].push_back(e);
                corrected[method].push_back(c);
            }
            std::printf(" %5.2f (%5.2f)", 100.0 * c, 100.0 * e);
        }
        std::printf("\n");
    }
    if (raw.empty()) return 0;
    std::printf("random directions: %zu; reference noise median %.2f%%\n", raw["used"].size(),
                100.0 * median(noises));
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
        if (mode == "judge" && argc == 7)
            return judge(argv[2], std::stoi(argv[3]), argv[4], argv[5], argv[6]);
        std::fprintf(stderr,
                     "usage: bench_relight directions N SEED | baked PACKAGE | look PACKAGE OUT.json | "
                     "judge PACKAGE FRAME LOOK.json DIRECTIONS.txt REF_PREFIX\n");
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_relight: %s\n", e.what());
        return 1;
    }
}
