#include "bake/scattered_light.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "bake/order_series.h"

namespace firelook::bake {
namespace {

// Seeds of chain c's passes: emission base, lights base + 1, order k base + 16 k (k <= 64); chains
// are 2^20 apart, so no two passes of a frame share a stream.
std::uint64_t chainSeed(std::uint64_t seed, int chain) { return seed + (std::uint64_t(1) << 20) * chain; }

}  // namespace

ScatteredLightTracer::ScatteredLightTracer(const TransportContext& ctx, const BasisModel& model,
                                           const TraceSettings& settings)
    : ctx_(ctx),
      settings_(settings),
      albedo_(model.albedo),
      counted_(model.relightFirstLight() >= 0 ? ctx.tables.bins + model.relightFirstLight()
                                              : ctx.tables.columns),
      chain_share_(settings.photon_noise_target > 0.0 ? settings.photon_pilot_share : 1.0),
      photons_primary_(
          std::max(1, static_cast<int>(std::lround(0.5 * chain_share_ * settings.photons_primary)))),
      photons_per_order_(
          std::max(1, static_cast<int>(std::lround(0.5 * chain_share_ * settings.photons_per_order)))),
      sum_(ctx.field_size, 0.0f),
      signed_sum_(ctx.field_size, 0.0f) {
    const TraceTables& tb = ctx.tables;
    const render::Medium& medium = ctx.medium;
    // Emission photons are drawn half by density and half equally per bin, so rare hot bins get as
    // many photons as common cool ones. Masses from cube centres, summed per z-layer of bricks (cube
    // layer by cube layer, brick by brick within each) and then in order: the same bytes with any
    // number of threads.
    const CubeCentres centres(medium);
    const int layers = medium.brickCounts().z;
    const int size = render::Medium::kBrickSize;
    std::vector<double> layer_mass(static_cast<size_t>(layers) * (1 + tb.bins), 0.0);
    tbb::parallel_for(0, layers, [&](int layer) {
        double* m = layer_mass.data() + static_cast<size_t>(layer) * (1 + tb.bins);
        const auto byZ = [](const glm::ivec3& b, int z) { return b.z < z; };
        const std::size_t first = std::lower_bound(centres.bricks.begin(), centres.bricks.end(), layer, byZ) -
                                  centres.bricks.begin();
        const std::size_t last =
            std::lower_bound(centres.bricks.begin(), centres.bricks.end(), layer + 1, byZ) -
            centres.bricks.begin();
        for (int z = 0; z < size; ++z)
            for (std::size_t b = first; b < last; ++b)
                for (int n = z * size * size; n < (z + 1) * size * size; ++n) {
                    const glm::vec2 v = centres.values[b * CubeCentres::kCubes + n];
                    if (!(v.x > 0.0f)) continue;
                    m[0] += v.x;
                    int first_bin, last_bin;
                    tb.binWindow(v.y, first_bin, last_bin);
                    for (int i = first_bin; i < last_bin; ++i) m[1 + i] += v.x * tb.rbf(i, v.y);
                }
    });
    double density_mass = 0.0;
    std::vector<double> bin_mass(tb.bins, 0.0);
    for (int layer = 0; layer < layers; ++layer) {
        density_mass += layer_mass[static_cast<size_t>(layer) * (1 + tb.bins)];
        for (int i = 0; i < tb.bins; ++i)
            bin_mass[i] += layer_mass[static_cast<size_t>(layer) * (1 + tb.bins) + 1 + i];
    }
    int active_bins = 0;
    for (double m : bin_mass) active_bins += m > 0.0;
    emission_sampler_ = std::make_unique<PhotonStartSampler>(
        medium, centres, [&tb, bin_mass, density_mass, active_bins](float rho, float t) {
            double per_bin = 0.0;
            int first, last;
            tb.binWindow(t, first, last);
            for (int i = first; i < last; ++i)
                if (bin_mass[i] > 0.0) per_bin += tb.rbf(i, t) / bin_mass[i];
            return rho * (0.5 / density_mass + 0.5 * per_bin / std::max(active_bins, 1));
        });
    density_sampler_ =
        std::make_unique<PhotonStartSampler>(medium, centres, [](float rho, float) { return double(rho); });
}

void ScatteredLightTracer::addChainPair(double size, const std::function<void(double)>& progress) {
    for (int i = 0; i < 2; ++i) traceChain(chains_, size, [&](double done) { progress((i + done) / 2); });
}

void ScatteredLightTracer::traceChain(int chain, double size, const std::function<void(double)>& progress) {
    const TraceTables& tb = ctx_.tables;
    const int G = tb.points, C = tb.columns;
    const std::uint64_t seed = chainSeed(settings_.seed, chain);
    const float weight = static_cast<float>(size);
    const float signed_weight = chain % 2 == 0 ? weight : -weight;
    const int photons_primary = std::max(1, static_cast<int>(std::lround(size * photons_primary_)));
    const double photons_per_order = size * photons_per_order_;
    const std::size_t row = static_cast<std::size_t>(G) * C;
    // Element by element, so on both cores in any split (same bytes): whole fields, once an order.
    const auto add = [&](const std::vector<float>& field, const float* factor) {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, field.size() / row, 256),
                          [&](const tbb::blocked_range<std::size_t>& slots) {
                              for (std::size_t r = slots.begin() * row; r < slots.end() * row; r += row)
                                  for (std::size_t j = 0; j < row; ++j) {
                                      const float v = factor ? factor[j] * field[r + j] : field[r + j];
                                      sum_[r + j] += weight * v;
                                      signed_sum_[r + j] += signed_weight * v;
                                  }
                          });
    };
    std::vector<float> order =
        photonPass(ctx_, SourceKind::Emission, *emission_sampler_, nullptr, photons_primary, seed, buffers_);
    progress(0.1);
    if (tb.lights > 0) {
        std::vector<float> light = photonPass(ctx_, SourceKind::LightScatter, *density_sampler_, nullptr,
                                              photons_primary, seed + 1, buffers_);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, order.size(), 1 << 16),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t i = r.begin(); i != r.end(); ++i) order[i] += light[i];
                          });
        buffers_.spare = std::move(light);
    }
    OrderSeries series(ctx_.cells, G, C, counted_, albedo_);
    series.add(order);
    add(order, nullptr);
    progress(0.2);
    for (int k = 2; k <= settings_.max_orders; ++k) {
        const double share = std::clamp(series.nextOrderShare(), settings_.min_order_photon_share, 1.0);
        const int photons = std::max(1, static_cast<int>(std::lround(share * photons_per_order)));
        order_photons_ += photons;
        order_photons_equal_ += std::lround(photons_per_order);
        std::vector<float> next = photonPass(ctx_, SourceKind::Scattered, *density_sampler_, &order, photons,
                                             seed + 16 * k, buffers_);
        buffers_.spare = std::move(order);
        order = std::move(next);
        series.add(order);
        add(order, nullptr);
        progress(0.2 + 0.8 * k / settings_.max_orders);
        if (series.converged(settings_.order_tolerance)) break;
    }
    // The orders not traced, as the geometric tail of each column's series (order_series.h).
    const std::vector<float> tail = series.tailFactors();
    add(order, tail.data());
    ++chains_;
    weight_ += size;
    orders_ = std::max(orders_, series.orders());
    last_order_fraction_ = std::max(last_order_fraction_, series.lastOrderFraction());
    tail_fraction_ = std::max(tail_fraction_, series.tailFraction());
}

std::vector<float> ScatteredLightTracer::estimate() && {
    const float inv = weight_ > 0.0 ? static_cast<float>(1.0 / weight_) : 1.0f;
    for (float& v : sum_) v *= inv;
    std::vector<float>().swap(signed_sum_);
    buffers_ = {};
    return std::move(sum_);
}

}  // namespace firelook::bake
