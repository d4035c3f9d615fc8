// scatter_order_report: where a bake's scattered light departs from the reference, order by order.
// For one frame of a sequence and one extinction (T_c, k_s, k_f), traces the basis at exactly that
// point (one-sample axes, so no grid interpolation and no compression) and compares the image mean
// of the light column alone (emission off) and of the emission columns alone (light off) against
// the reference path tracer cut after 1, 2, 3 and all scattering events. The basis's matching cut
// is its number of photon passes (`max_orders`): the light's single scattering is on the camera
// rays, so light order m is m - 1 passes; emission order m is m passes.
// Built, not a ctest test: it is how the scattered-light bias of issue 27 was found.
//   scatter_order_report SEQUENCE FRAME WxH T_c k_s k_f albedo SPP [key=value ...]
//   ORDERS="01a" in the environment limits the cuts (digits, a = all); CLAMP_EXTREME=1 clamps extreme values.
//   keys: the trace settings cell_voxels, max_cells_per_axis, light_points_per_axis, step_voxels, photons_primary,
//         photons_per_order, max_orders (for the "all" column), order_tolerance, seed; up=z|y
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bake/basis_tracer.h"
#include "bake/scene_setup.h"
#include "reference/frame_medium.h"
#include "render/reference_tracer.h"

using namespace firelook;

namespace {

double imageMean(const std::vector<float>& rgba) {
    double sum = 0.0;
    for (size_t i = 0; i < rgba.size(); i += 4) sum += rgba[i];
    return sum / static_cast<double>(rgba.size() / 4);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 9) {
        std::fprintf(stderr, "usage: %s SEQUENCE FRAME WxH T_c k_s k_f albedo SPP [key=value ...]\n", argv[0]);
        return 2;
    }
    const int frame = std::atoi(argv[2]);
    const ExtinctionParams theta{std::atof(argv[4]), std::atof(argv[5]), std::atof(argv[6])};
    const double albedo = std::atof(argv[7]);
    const int spp = std::atoi(argv[8]);
    bake::TraceSettings trace;
    bake::SceneOptions options;
    options.up = render::UpAxis::Z;
    for (int i = 9; i < argc; ++i) {
        const std::string kv = argv[i];
        const size_t eq = kv.find('=');
        if (eq == std::string::npos) return std::fprintf(stderr, "not key=value: %s\n", argv[i]), 2;
        const std::string key = kv.substr(0, eq);
        const double v = std::atof(kv.c_str() + eq + 1);
        if (key == "cell_voxels") trace.cell_voxels = static_cast<int>(v);
        else if (key == "max_cells_per_axis") trace.max_cells_per_axis = static_cast<int>(v);
        else if (key == "light_points_per_axis") trace.light_points_per_axis = static_cast<int>(v);
        else if (key == "step_voxels") trace.step_voxels = v;
        else if (key == "photons_primary") trace.photons_primary = static_cast<int>(v);
        else if (key == "photons_per_order") trace.photons_per_order = static_cast<int>(v);
        else if (key == "max_orders") trace.max_orders = static_cast<int>(v);
        else if (key == "order_tolerance") trace.order_tolerance = v;
        else if (key == "seed") trace.seed = static_cast<uint64_t>(v);
        else if (key == "up") options.up = kv.substr(eq + 1) == "y" ? render::UpAxis::Y : render::UpAxis::Z;
        else return std::fprintf(stderr, "unknown key: %s\n", key.c_str()), 2;
    }
    // CLAMP_EXTREME=1 reads as --clamp-extreme does (the hard case of four 1e30 voxels).
    const vdb::VdbSequence sequence = vdb::VdbSequence::open(argv[1], {.clamp_extreme = std::getenv("CLAMP_EXTREME") != nullptr});
    std::tie(options.width, options.height) = bake::parseSize(argv[3]);
    const bake::SceneSetup scene = bake::resolveScene(sequence, options);
    const render::Medium medium = reference::mediumFromFrame(sequence.load(frame));
    const auto [t_lo, t_hi] = bake::sequenceTemperatureRange(sequence);

    bake::BasisModel model;
    model.bins = {t_lo, t_hi, 16};
    model.rbf_width = kDefaultRbfWidth;
    model.albedo = albedo;
    model.axes = {{theta.temperature_threshold}, {theta.smoke_extinction}, {theta.flame_extinction}};
    model.alpha_thresholds = model.axes.temperature_threshold;
    model.light_directions = {scene.light_directions.front()};
    const int bins = model.bins.count, columns = bins + 1;

    LookModel look;
    look.bins = model.bins;
    look.extinction = theta;
    look.albedo = albedo;
    look.emission.basis = {model.bins, model.rbf_width};
    // Emission: unit coefficients on the upper half of the bins (where flame is).
    std::vector<Rgb> emission(bins, Rgb(0.0f));
    for (int i = bins / 2; i < bins; ++i) emission[i] = Rgb(1.0f);
    const auto basisMean = [&](const bake::FrameBasis& b, bool light) {
        double sum = 0.0;
        const size_t pixels = static_cast<size_t>(b.width) * b.height;
        for (size_t p = 0; p < pixels; ++p) {
            const float* row = b.matrix.data() + p * columns;
            if (light) sum += row[bins];
            else
                for (int i = 0; i < bins; ++i) sum += emission[i][0] * row[i];
        }
        return sum / static_cast<double>(pixels);
    };
    const auto referenceMean = [&](bool light, int order, double& noise) {
        LookModel l = look;
        l.emission.coefficients = light ? std::vector<Rgb>(bins, Rgb(0.0f)) : emission;
        l.lights = {{model.light_directions[0], light ? Rgb(1.0f) : Rgb(0.0f)}};
        render::ReferenceSettings rs;
        rs.samples_per_pixel = spp;
        rs.seed = 7;
        rs.max_scattering_order = order;
        const render::ReferenceResult r = render::renderReference(medium, l, scene.camera, rs);
        double sq = 0.0, sum = 0.0;
        for (size_t i = 0; i < r.image.rgba.size(); i += 4) sum += r.image.rgba[i], sq += double(r.image.rgba[i]) * r.image.rgba[i];
        noise = sum > 0.0 ? r.estimated_relative_rmse * std::sqrt(sq) / sum : 0.0;
        return imageMean(r.image.rgba);
    };
    std::printf("frame %d %dx%d T_c %.3f k_s %.3f k_f %.3f albedo %.2f, %d spp\n", frame, options.width,
                options.height, theta.temperature_threshold, theta.smoke_extinction, theta.flame_extinction, albedo, spp);
    const int all_orders = trace.max_orders;
    std::vector<int> orders = {0, 1, 2, 3, INT_MAX};
    if (const char* only = std::getenv("ORDERS")) {
        orders.clear();
        for (const char* c = only; *c; ++c)
            if (*c >= '0' && *c <= '9') orders.push_back(*c - '0');
            else if (*c == 'a') orders.push_back(INT_MAX);
    }
    for (int order : orders) {
        for (bool light : {true, false}) {
            if (light && order == 0) continue;
            const int passes = order == INT_MAX ? all_orders : (light ? order - 1 : order);
            bake::TraceSettings t = trace;
            t.max_orders = passes;
            if (order != INT_MAX) t.order_tolerance = 0.0;
            const bake::FrameBasis b = bake::traceFrameBasis(medium, scene.camera, model, t);
            double noise = 0.0;
            const double ref = referenceMean(light, order, noise);
            const double got = basisMean(b, light);
            std::printf("  %-8s orders %-3s basis %.6e reference %.6e ratio %.4f (reference noise of the mean %.4f, "
                        "passes %d)\n",
                        light ? "light" : "emission", order == INT_MAX ? "all" : std::to_string(order).c_str(), got,
                        ref, ref > 0.0 ? got / ref : 0.0, noise, b.scattering_orders);
            std::fflush(stdout);
        }
    }
    return 0;
}
