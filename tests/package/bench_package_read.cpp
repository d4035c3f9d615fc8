// Package read throughput in MB/s of raw bytes delivered (not a ctest test; run by hand):
//   bench_package_read --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
// Data: 16 sections of 1024 x 1024 float32 (64 MiB raw) that look like image factors, a smooth
// field plus noise. Each iteration opens the package afresh, so every section's checksum is
// verified once per iteration, as on a first use at runtime. The file stays in the page cache:
// this measures the reader, not the disk.

#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>

#include "package/container_reader.h"
#include "package/container_writer.h"

namespace firelook::package {
namespace {

constexpr uint32_t kFactors = makeFourCC('F', 'A', 'C', 'T');
constexpr uint32_t kSectionCount = 16;
constexpr std::size_t kFloatsPerSection = 1024 * 1024;
constexpr double kRawBytes = double(kSectionCount) * kFloatsPerSection * sizeof(float);

std::vector<float> imageFactor(uint32_t seed) {
    std::mt19937 random(seed);
    std::normal_distribution<float> noise(0.0f, 0.02f);
    std::vector<float> values(kFloatsPerSection);
    for (std::size_t i = 0; i < values.size(); ++i) {
        const float x = static_cast<float>(i % 1024) / 1024.0f;
        const float y = static_cast<float>(i / 1024) / 1024.0f;
        values[i] = std::exp(-8.0f * ((x - 0.5f) * (x - 0.5f) + (y - 0.4f) * (y - 0.4f))) *
                        std::sin(9.0f * x + 3.0f * y + static_cast<float>(seed)) +
                    noise(random);
    }
    return values;
}

// Writes the two packages once per process and removes them at exit.
class BenchPackages {
  public:
    BenchPackages() {
        folder_ =
            std::filesystem::temp_directory_path() / ("firelook-bench-package-" + std::to_string(::getpid()));
        std::filesystem::create_directories(folder_);
        ContainerWriter raw(rawPath(), WriterOptions{.zstd_level = 3, .format_minor = kFormatMinor});
        ContainerWriter zstd(zstdPath(), WriterOptions{.zstd_level = 3, .format_minor = kFormatMinor});
        for (uint32_t frame = 0; frame < kSectionCount; ++frame) {
            const std::vector<float> values = imageFactor(frame);
            const auto bytes = std::as_bytes(std::span(values));
            raw.addSection(kFactors, frame, bytes, Codec::Raw);
            zstd.addSection(kFactors, frame, bytes, Codec::Zstd);
        }
        raw.commit();
        zstd.commit();
    }
    ~BenchPackages() {
        std::error_code ignored;
        std::filesystem::remove_all(folder_, ignored);
    }
    std::filesystem::path rawPath() const { return folder_ / "raw.firelook"; }
    std::filesystem::path zstdPath() const { return folder_ / "zstd.firelook"; }

  private:
    std::filesystem::path folder_;
};

const BenchPackages& packages() {
    static const BenchPackages instance;
    return instance;
}

void reportRate(benchmark::State& state, const std::filesystem::path& file) {
    state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * kRawBytes));
    state.counters["MB/s"] = benchmark::Counter(static_cast<double>(state.iterations()) * kRawBytes / 1e6,
                                                benchmark::Counter::kIsRate);
    state.counters["stored/raw"] = static_cast<double>(std::filesystem::file_size(file)) / kRawBytes;
}

// (a) Raw codec: zero-copy views of the mapping, checksum verified on first use.
void BM_RawMappedViewWithChecksum(benchmark::State& state) {
    const auto& file = packages().rawPath();
    for (auto _ : state) {
        const ContainerReader reader = ContainerReader::open(file);
        for (const SectionInfo& section : reader.sections())
            benchmark::DoNotOptimize(reader.mapped(section).data());
    }
    reportRate(state, file);
}
BENCHMARK(BM_RawMappedViewWithChecksum)->Unit(benchmark::kMillisecond)->UseRealTime();

// (b) Zstd codec: read() verifies the checksum of the stored bytes and decompresses.
void BM_ZstdRead(benchmark::State& state) {
    const auto& file = packages().zstdPath();
    for (auto _ : state) {
        const ContainerReader reader = ContainerReader::open(file);
        for (const SectionInfo& section : reader.sections())
            benchmark::DoNotOptimize(reader.read(section).data());
    }
    reportRate(state, file);
}
BENCHMARK(BM_ZstdRead)->Unit(benchmark::kMillisecond)->UseRealTime();

// Reference in the same run: Raw codec through read(), i.e. checksum plus one copy into a new vector.
void BM_RawReadCopy(benchmark::State& state) {
    const auto& file = packages().rawPath();
    for (auto _ : state) {
        const ContainerReader reader = ContainerReader::open(file);
        for (const SectionInfo& section : reader.sections())
            benchmark::DoNotOptimize(reader.read(section).data());
    }
    reportRate(state, file);
}
BENCHMARK(BM_RawReadCopy)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace firelook::package

BENCHMARK_MAIN();
