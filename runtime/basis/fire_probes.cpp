#include "basis/fire_probes.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/geometric.hpp>
#include <numbers>

#include "basis/section_bytes.h"
#include "common/error.h"

namespace firelook::basis {
namespace {

constexpr size_t kProbeHeaderBytes = 40 + 10 * 8;
constexpr int kMaxProbesPerAxis = 64;

bool finite3(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

std::vector<std::byte> encodeFireProbes(const FireProbeTable& t) {
    std::vector<std::byte> out;
    out.reserve(kProbeHeaderBytes + t.sh.size() * 4);
    putSectionValue<uint32_t>(out, kFireProbesVersion);
    for (int i = 0; i < 3; ++i) putSectionValue<uint32_t>(out, static_cast<uint32_t>(t.grid.counts[i]));
    putSectionValue<uint32_t>(out, static_cast<uint32_t>(t.points));
    putSectionValue<uint32_t>(out, static_cast<uint32_t>(t.bins));
    putSectionValue<uint32_t>(out, kFireProbeCoefficients);
    putSectionValue<uint32_t>(out, static_cast<uint32_t>(t.rank));
    putSectionValue<float>(out, t.extinction_scale);
    putSectionValue<uint32_t>(out, 0);
    for (const glm::dvec3* v : {&t.grid.origin, &t.grid.spacing, &t.grid.falloff_centre})
        for (int i = 0; i < 3; ++i) putSectionValue<double>(out, (*v)[i]);
    putSectionValue<double>(out, t.grid.falloff_radius);
    for (float v : t.factors) putSectionValue<float>(out, v);
    for (float v : t.sh) putSectionValue<float>(out, v);
    return out;
}

FireProbeTable decodeFireProbes(std::span<const std::byte> bytes, int points, int bins,
                                const std::string& where) {
    const auto fail = [&](const std::string& what) {
        throw Error(ErrorCode::Corrupt, where + ": fire probes " + what);
    };
    if (bytes.size() < kProbeHeaderBytes)
        fail("section is " + std::to_string(bytes.size()) + " bytes, too short");
    size_t at = 0;
    const uint32_t version = getSectionValue<uint32_t>(bytes, at);
    if (version != kFireProbesVersion) fail("have an unknown version " + std::to_string(version));
    FireProbeTable t;
    uint32_t counts[3];
    for (uint32_t& c : counts) c = getSectionValue<uint32_t>(bytes, at);
    const uint32_t p = getSectionValue<uint32_t>(bytes, at), b = getSectionValue<uint32_t>(bytes, at),
                   coefficients = getSectionValue<uint32_t>(bytes, at),
                   rank = getSectionValue<uint32_t>(bytes, at);
    t.extinction_scale = getSectionValue<float>(bytes, at);
    at += 4;
    for (glm::dvec3* v : {&t.grid.origin, &t.grid.spacing, &t.grid.falloff_centre})
        for (int i = 0; i < 3; ++i) (*v)[i] = getSectionValue<double>(bytes, at);
    t.grid.falloff_radius = getSectionValue<double>(bytes, at);
    for (int i = 0; i < 3; ++i) {
        if (counts[i] < 2 || counts[i] > kMaxProbesPerAxis)
            fail("have " + std::to_string(counts[i]) + " probes along an axis, not 2 to " +
                 std::to_string(kMaxProbesPerAxis));
        t.grid.counts[i] = static_cast<int>(counts[i]);
    }
    if (coefficients != kFireProbeCoefficients)
        fail("have " + std::to_string(coefficients) + " coefficients a probe, not " +
             std::to_string(kFireProbeCoefficients));
    if (p != static_cast<uint32_t>(points) || b != static_cast<uint32_t>(bins))
        fail("are for " + std::to_string(p) + " grid points and " + std::to_string(b) +
             " bins, the package has " + std::to_string(points) + " and " + std::to_string(bins));
    const uint32_t max_rank = std::min<uint32_t>(p, kMaxFireProbeRank);
    if (rank < 1 || rank > max_rank)
        fail("have rank " + std::to_string(rank) + ", not 1 to " + std::to_string(max_rank));
    if (!std::isfinite(t.extinction_scale) || t.extinction_scale < 0.0f) fail("have a bad extinction scale");
    if (!finite3(t.grid.origin) || !finite3(t.grid.falloff_centre) || !std::isfinite(t.grid.falloff_radius) ||
        t.grid.falloff_radius < 0.0)
        fail("have a non-finite placement");
    if (!finite3(t.grid.spacing) ||
        !(t.grid.spacing.x > 0.0 && t.grid.spacing.y > 0.0 && t.grid.spacing.z > 0.0))
        fail("have a spacing that is not positive");
    t.points = points;
    t.bins = bins;
    t.rank = static_cast<int>(rank);
    const size_t factors = size_t{p} * rank;
    const size_t values = static_cast<size_t>(t.grid.probes()) * rank * b * kFireProbeCoefficients;
    if (bytes.size() != kProbeHeaderBytes + (factors + values) * 4)
        fail("section is " + std::to_string(bytes.size()) + " bytes, expected " +
             std::to_string(kProbeHeaderBytes + (factors + values) * 4));
    t.factors.resize(factors);
    std::memcpy(t.factors.data(), bytes.data() + at, factors * 4);
    t.sh.resize(values);
    std::memcpy(t.sh.data(), bytes.data() + at + factors * 4, values * 4);
    for (const std::vector<float>* part : {&t.factors, &t.sh})
        for (float v : *part)
            if (!std::isfinite(v)) fail("have a non-finite value");
    return t;
}

void evaluateFireProbes(const FireProbeTable& t, const GridWeights& weights, std::span<const Rgb> rbf,
                        Rgb* out) {
    constexpr int K = kFireProbeCoefficients;
    // The grid weights on the factors first: one weight a term.
    double term[kMaxFireProbeRank];
    const int rank = std::min(t.rank, kMaxFireProbeRank);
    std::fill(term, term + rank, 0.0);
    for (int w = 0; w < weights.count; ++w)
        for (int r = 0; r < rank; ++r)
            term[r] += static_cast<double>(weights.weight[w]) *
                       t.factors[static_cast<size_t>(weights.point[w]) * t.rank + r];
    for (int probe = 0; probe < t.grid.probes(); ++probe) {
        glm::dvec3 sum[K];
        std::fill(sum, sum + K, glm::dvec3(0.0));
        for (int r = 0; r < rank; ++r) {
            if (term[r] == 0.0) continue;
            for (int i = 0; i < t.bins; ++i) {
                const glm::dvec3 ci = glm::dvec3(rbf[i]) * term[r];
                const float* v = t.at(probe, r, i);
                for (int k = 0; k < K; ++k) sum[k] += ci * static_cast<double>(v[k]);
            }
        }
        for (int k = 0; k < K; ++k) out[probe * K + k] = Rgb(sum[k]);
    }
}

void sampleFireProbes(const FireProbeGrid& grid, std::span<const Rgb> values, const glm::dvec3& point,
                      Rgb* out) {
    constexpr int K = kFireProbeCoefficients;
    if (!std::isfinite(point.x) || !std::isfinite(point.y) || !std::isfinite(point.z)) {
        std::fill(out, out + K, Rgb(0.0f));  // no cell to read: nothing, rather than a NaN
        return;
    }
    // Cell and fractions, clamped to the grid: outside it the nearest face's values.
    int cell[3];
    double frac[3];
    for (int a = 0; a < 3; ++a) {
        const double u =
            std::clamp((point[a] - grid.origin[a]) / grid.spacing[a], 0.0, double(grid.counts[a] - 1));
        cell[a] = std::min(static_cast<int>(u), grid.counts[a] - 2);
        frac[a] = u - cell[a];
    }
    const bool falloff = grid.falloff_radius > 0.0;
    const double r2 = grid.falloff_radius * grid.falloff_radius;
    const auto s = [&](const glm::dvec3& x) {
        const glm::dvec3 d = x - grid.falloff_centre;
        return glm::dot(d, d) + r2;
    };
    const double s_point = falloff ? s(point) : 1.0;
    glm::dvec3 sum[K];
    std::fill(sum, sum + K, glm::dvec3(0.0));
    for (int corner = 0; corner < 8; ++corner) {
        const int i = cell[0] + (corner & 1), j = cell[1] + ((corner >> 1) & 1), k = cell[2] + (corner >> 2);
        double w = ((corner & 1) ? frac[0] : 1.0 - frac[0]) *
                   (((corner >> 1) & 1) ? frac[1] : 1.0 - frac[1]) *
                   ((corner >> 2) ? frac[2] : 1.0 - frac[2]);
        if (w == 0.0) continue;
        if (falloff) w *= s(grid.position(i, j, k)) / s_point;
        const Rgb* v = values.data() + static_cast<size_t>(i + grid.counts.x * (j + grid.counts.y * k)) * K;
        for (int c = 0; c < K; ++c) sum[c] += w * glm::dvec3(v[c]);
    }
    for (int c = 0; c < K; ++c) out[c] = Rgb(sum[c]);
}

// Y00 and the factor of the three Y1m: 1 / (2 sqrt(pi)) and sqrt(3) times that.
constexpr double kY00 = 0.28209479177387814, kY1 = 0.4886025119029199;

void shBasis(const glm::dvec3& d, double* y) {
    y[0] = kY00;
    y[1] = kY1 * d.y;
    y[2] = kY1 * d.z;
    y[3] = kY1 * d.x;
    y[4] = 1.0925484305920792 * d.x * d.y;
    y[5] = 1.0925484305920792 * d.y * d.z;
    y[6] = 0.31539156525252005 * (3.0 * d.z * d.z - 1.0);
    y[7] = 1.0925484305920792 * d.x * d.z;
    y[8] = 0.5462742152960396 * (d.x * d.x - d.y * d.y);
}

Rgb fluenceFromSh(const Rgb* sh) {
    glm::dvec3 f = 2.0 * std::sqrt(std::numbers::pi) * glm::dvec3(sh[0]);
    for (int c = 0; c < 3; ++c)
        f[c] = f[c] > 0.0 ? f[c] : 0.0;  // a blend with negative weights can dip below
    return Rgb(f);
}

double directionalShare(double l00, double l1_length) {
    if (!(l00 > 0.0) || !(l1_length > 0.0)) return 0.0;
    const double q = std::min(1.0, l1_length / (std::sqrt(3.0) * l00));
    const double x = std::clamp(4.0 * q - 3.0, 0.0, 1.0);
    return x * std::sqrt(x);
}

Rgb irradianceFromSh(const Rgb* sh, const glm::dvec3& normal) {
    constexpr double pi = std::numbers::pi;
    static constexpr double kBand[kFireProbeCoefficients] = {
        pi, 2 * pi / 3, 2 * pi / 3, 2 * pi / 3, pi / 4, pi / 4, pi / 4, pi / 4, pi / 4};
    // Order 2 rings below 0 where little light arrives; a NaN (a zero normal) gives 0 too.
    const auto positive = [](double v) { return v > 0.0 ? v : 0.0; };
    double y[kFireProbeCoefficients];
    shBasis(normal, y);
    Rgb out;
    for (int c = 0; c < 3; ++c) {
        double sh_only = 0.0;
        for (int k = 0; k < kFireProbeCoefficients; ++k) sh_only += kBand[k] * y[k] * double(sh[k][c]);
        const glm::dvec3 l1(sh[3][c], sh[1][c], sh[2][c]);  // (x, y, z): Y11, Y1-1, Y10
        const double length = glm::length(l1);
        const double w = directionalShare(sh[0][c], length);
        if (!(w > 0.0)) {
            out[c] = static_cast<float>(positive(sh_only));
            continue;
        }
        // The light from d = l1 / |l1| of the intensity whose projection has that L1 (at most what
        // L00 allows), and the rest of the coefficients after it, by the SH rule.
        const glm::dvec3 d = l1 / length;
        const double intensity = std::min(length / kY1, double(sh[0][c]) / kY00);
        double yd[kFireProbeCoefficients];
        shBasis(d, yd);
        double split = intensity * positive(glm::dot(normal, d));
        for (int k = 0; k < kFireProbeCoefficients; ++k)
            split += kBand[k] * y[k] * (double(sh[k][c]) - intensity * yd[k]);
        out[c] = static_cast<float>(w * positive(split) + (1.0 - w) * positive(sh_only));
    }
    return out;
}

}  // namespace firelook::basis
