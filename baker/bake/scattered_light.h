// The scattered light of one frame (basis_tracer.h, step 2): Lbar summed over every scattering order,
// from independent photon chains, with a field that measures its own photon noise.
//
// A chain is one complete estimate: the primary passes (emission, the lights' single scattering),
// then one pass per further order from the previous order's field, until its OrderSeries converges,
// then the geometric tail. Chains use disjoint seeds, so they are independent; a chain of size w
// (its photons as a multiple of a pilot chain's) has the covariance of a pilot chain over w. The
// estimate is the chains' mean weighted by size, E = sum w_i A_i / W (W = sum w_i), and their signed
// mean S = sum s_i w_i A_i / W, with signs s_i = +-1 such that sum s_i w_i = 0, has zero expectation
// and exactly E's photon noise covariance (both are sum w_i^2 Cov(A_i) / W^2 = Cov(A_1) / W),
// including the noise each order hands on to the next. Chains come in pairs of one size with
// opposite signs, which keeps sum s_i w_i = 0. photon_noise.h carries S through the camera to
// predict each column's image noise; the tracer adds one pair of chains of the size that prediction
// asks for to meet TraceSettings::photon_noise_target.
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "bake/basis_tracer.h"
#include "bake/photon_pass.h"
#include "bake/photon_start_sampler.h"

namespace firelook::bake {

class ScatteredLightTracer {
  public:
    // Photons per chain: half of settings.photons_primary / photons_per_order, so two chains hold
    // what those settings name; times photon_pilot_share when there is a noise target.
    ScatteredLightTracer(const TransportContext& ctx, const BasisModel& model, const TraceSettings& settings);

    // Traces two more chains of `size` pilot chains' photons each (size > 0), a + and a - one.
    // progress(done) gets the share of the pair done; it may throw to cancel (a cancelled trace
    // leaves the fields meaningless).
    void addChainPair(double size, const std::function<void(double)>& progress);

    int chains() const { return chains_; }
    // The photons of a pilot chain as a share of half the settings' photons (1, or photon_pilot_share).
    double chainShare() const { return chain_share_; }
    // The chains' sizes summed (W above): the photons traced, in pilot chains.
    double weight() const { return weight_; }
    // Photons traced so far / the photons the settings name.
    double photonMultiple() const { return 0.5 * chain_share_ * weight_; }
    // The chains' sums weighted by size, plain and signed: divided by weight(), the estimate and
    // its noise sample.
    const std::vector<float>& sum() const { return sum_; }
    const std::vector<float>& signedSum() const { return signed_sum_; }
    // Ends the tracing: the chains' weighted mean, moved out.
    std::vector<float> estimate() &&;

    // Columns 0..counted-1 of each grid point decide the orders and the photon budget; six-way or
    // sphere lights (basis/six_way_lights.h, basis/sphere_lights.h) come after them and never change
    // either, so every other column is the same bytes as in a bake without them.
    int countedColumns() const { return counted_; }
    int orders() const { return orders_; }  // the most any chain traced
    double lastOrderFraction() const { return last_order_fraction_; }
    double tailFraction() const { return tail_fraction_; }
    // Photons the further orders were traced with, as a share of every order at photons_per_order
    // (TraceSettings::min_order_photon_share; 1 before any order).
    double orderPhotonShare() const {
        return order_photons_equal_ > 0 ? static_cast<double>(order_photons_) / order_photons_equal_ : 1.0;
    }

  private:
    void traceChain(int chain, double size, const std::function<void(double)>& progress);

    const TransportContext& ctx_;
    const TraceSettings& settings_;
    double albedo_;
    int counted_;
    double chain_share_;
    int photons_primary_, photons_per_order_;
    std::unique_ptr<PhotonStartSampler> emission_sampler_, density_sampler_;
    std::vector<float> sum_, signed_sum_;
    PhotonPassBuffers buffers_;  // the photon passes' accumulation buffers, zero between passes
    int chains_ = 0;
    double weight_ = 0.0;
    int orders_ = 0;
    double last_order_fraction_ = 0.0, tail_fraction_ = 0.0;
    long long order_photons_ = 0, order_photons_equal_ = 0;
};

}  // namespace firelook::bake
