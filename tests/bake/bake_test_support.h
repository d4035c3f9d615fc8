// Small scenes shared by the bake tests: a homogeneous box seen head-on by a narrow camera, and the
// basis model / look that go with it.
#pragma once

#include <cmath>
#include <glm/vec3.hpp>
#include <numbers>
#include <vector>

#include "bake/basis_tracer.h"
#include "look/look_model.h"
#include "render/camera.h"
#include "render/medium.h"

namespace firelook::bake::test {

inline double degrees(double d) { return d * std::numbers::pi / 180.0; }

// A unit box centred on the origin, 8^3 voxels (edge 0.125), uniform density and temperature.
inline render::Medium unitBox(float density, float temperature, int voxels = 8) {
    return render::Medium::homogeneousBox(glm::dvec3(1.0), glm::ivec3(voxels), density, temperature);
}

// Looks down -Z at the origin from z = 3. With a 10 degree field of view every pixel-centre ray
// crosses the box's front and back faces at |x|, |y| < 3.5 tan(5 deg) = 0.31, inside the region
// where the box's density is flat (|x|, |y| < 0.5 - 0.0625), so its path length is 1 / |dir.z|.
inline render::Camera headOnCamera(int size, double fov_degrees = 10.0) {
    return render::Camera::lookAt({0.0, 0.0, 3.0}, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, degrees(fov_degrees),
                                  size, size);
}

// Temperatures [0, 1] in `bins` bins, one light travelling straight down (-Y).
inline BasisModel basisModel(int bins, double albedo, const basis::ParameterAxes& axes) {
    BasisModel m;
    m.bins = {0.0, 1.0, bins};
    m.rbf_width = kDefaultRbfWidth;
    m.albedo = albedo;
    m.axes = axes;
    m.light_directions = {{0.0, -1.0, 0.0}};
    m.alpha_thresholds = axes.temperature_threshold;
    return m;
}

// Few photons, so that the whole suite stays fast under sanitizers; as many as given (no noise
// target: it would multiply so few photons by max_photon_scale).
inline TraceSettings fastTrace(uint64_t seed = 1) {
    TraceSettings s;
    s.photons_primary = 2000;
    s.photons_per_order = 2000;
    s.photon_noise_target = 0.0;
    s.max_orders = 8;
    s.seed = seed;
    return s;
}

// Column `column` of grid point `point` of one pixel.
inline float basisValue(const FrameBasis& b, const BasisModel& m, int pixel, int point, int column) {
    return b.matrix[static_cast<size_t>(pixel) * b.columns +
                    static_cast<size_t>(point) * m.columnsPerPoint() + column];
}

// The look's image from the uncompressed basis at one grid point: sum_i c_i B_i + sum_l E_l B_l.
inline std::vector<float> recombineAtPoint(const FrameBasis& b, const BasisModel& m, int point,
                                           const std::vector<Rgb>& c, const std::vector<Rgb>& e) {
    const int pixels = b.width * b.height;
    std::vector<float> rgba(static_cast<size_t>(pixels) * 4, 0.0f);
    for (int p = 0; p < pixels; ++p) {
        Rgb sum(0.0f);
        for (int i = 0; i < m.bins.count; ++i) sum += c[i] * basisValue(b, m, p, point, i);
        for (size_t l = 0; l < e.size(); ++l) sum += e[l] * basisValue(b, m, p, point, m.bins.count + int(l));
        for (int ch = 0; ch < 3; ++ch) rgba[p * 4 + ch] = sum[ch];
    }
    return rgba;
}

// alpha = mean over the pixel's footprint rays of 1 - exp(-(a O_a + b O_b)), from the traced depth
// maps (alpha threshold `a_index`; layouts as in FrameBasis).
inline double depthAlpha(const FrameBasis& b, int pixel, int a_index, const ExtinctionParams& theta) {
    const size_t pixels = static_cast<size_t>(b.width) * b.height;
    const size_t samples = static_cast<size_t>(b.footprint_samples);
    const size_t thresholds = b.depth_a.size() / (samples * pixels);
    double sum = 0.0;
    for (size_t s = 0; s < samples; ++s) {
        const double tau = theta.a() * b.depth_a[(s * thresholds + a_index) * pixels + pixel] +
                           theta.b() * b.depth_b[s * pixels + pixel];
        sum += 1.0 - std::exp(-tau);
    }
    return sum / double(samples);
}

}  // namespace firelook::bake::test
