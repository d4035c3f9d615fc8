// Random numbers for Monte Carlo estimators: small, fast and reproducible.
#pragma once

#include <cstdint>

namespace firelook::render {

// splitmix64's finaliser: a bijective 64-bit mix, used to turn (seed, pixel, sample) into
// well-separated generator seeds.
constexpr std::uint64_t mixBits(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}

// PCG32 (O'Neill, pcg-random.org, "pcg32_random_r"): 64-bit state, 32-bit output.
class Pcg32 {
  public:
    explicit Pcg32(std::uint64_t seed) {
        nextUint32();
        state_ += seed;
        nextUint32();
    }

    // The generator for one sample of one pixel: the stream depends only on these three numbers,
    // so images do not depend on how pixels are scheduled across threads.
    static Pcg32 forSample(std::uint64_t seed, std::uint64_t pixel, std::uint64_t sample) {
        return Pcg32(mixBits(mixBits(mixBits(seed) ^ pixel) ^ sample));
    }

    std::uint32_t nextUint32() {
        const std::uint64_t old = state_;
        state_ = old * 6364136223846793005ULL + kIncrement;
        const auto xorshifted = static_cast<std::uint32_t>(((old >> 18u) ^ old) >> 27u);
        const auto rotation = static_cast<std::uint32_t>(old >> 59u);
        return (xorshifted >> rotation) | (xorshifted << ((32u - rotation) & 31u));
    }

    // Uniform in [0, 1) with 2^-32 resolution, so 1 - uniform() is never 0.
    double uniform() { return nextUint32() * 0x1p-32; }

  private:
    static constexpr std::uint64_t kIncrement = 1442695040888963407ULL;
    std::uint64_t state_ = 0;
};

}  // namespace firelook::render
