// Time to load and to densify one frame of the bundled explosion:
//   firelook_vdb_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include "vdb/vdb_sequence.h"

namespace {

using firelook::vdb::VdbSequence;

void BM_OpenSequence(benchmark::State& state) {
    for (auto _ : state) benchmark::DoNotOptimize(VdbSequence::open(FIRELOOK_SAMPLE_DIR));
}
BENCHMARK(BM_OpenSequence)->Unit(benchmark::kMillisecond);

void BM_LoadFrame(benchmark::State& state) {
    const VdbSequence sequence = VdbSequence::open(FIRELOOK_SAMPLE_DIR);
    for (auto _ : state) benchmark::DoNotOptimize(sequence.load(static_cast<int>(state.range(0))));
}
BENCHMARK(BM_LoadFrame)->Arg(1)->Arg(6)->Arg(12)->Unit(benchmark::kMillisecond);

void BM_ToDense(benchmark::State& state) {
    const VdbSequence sequence = VdbSequence::open(FIRELOOK_SAMPLE_DIR);
    const auto frame = sequence.load(static_cast<int>(state.range(0)));
    for (auto _ : state) benchmark::DoNotOptimize(toDense(frame));
    state.counters["voxels"] = static_cast<double>(toDense(frame).voxelCount());
}
BENCHMARK(BM_ToDense)->Arg(1)->Arg(6)->Arg(12)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
