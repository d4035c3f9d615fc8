// Fuzz target: bytes -> fire_0001.vdb in a scratch folder -> VdbSequence::open, load, toDense.
//
// Contract checked: every failure is a VdbError naming the file (vdb_sequence.h); a loaded frame
// has finite statistics, a density >= 0 (NaN/Inf/negatives are cleaned by default) and a dense copy
// of the advertised size. Frames whose dense box would exceed 2^22 voxels are not densified: the
// harness tests logic, not memory (toDense itself refuses more than 2^31).
//
// OpenVDB parses only a file that passed checkFileStructure (vdb/file_structure.h): a crash inside
// OpenVDB's own code is a gap in that check (see README.md).
#include <cmath>
#include <string>

#include "fuzz_support.h"
#include "vdb/dense_volume.h"
#include "vdb/vdb_sequence.h"

namespace {

using namespace firelook;
constexpr const char* kTarget = "fuzz_vdb_sequence";
constexpr const char* kFileName = "fire_0001.vdb";

void checkNamesFile(const std::exception& e) {
    if (!fuzz::contains(e.what(), kFileName) && !fuzz::contains(e.what(), "firelook-fuzz-"))
        fuzz::fail(kTarget, std::string("error does not name the file: ") + e.what());
}

void checkFrame(const vdb::VolumeFrame& frame) {
    for (const vdb::GridStats* stats : {&frame.density_stats, &frame.temperature_stats})
        if (!std::isfinite(stats->min) || !std::isfinite(stats->max) || stats->min > stats->max)
            fuzz::fail(kTarget, "grid statistics not finite or min > max");
    if (frame.density_stats.min < 0.0) fuzz::fail(kTarget, "negative density survived cleaning");
    const vdb::IndexBox& box = frame.index_bounds;
    double voxels = 1.0;
    for (int a = 0; a < 3; ++a) voxels *= double(box.max[a]) - double(box.min[a]) + 3.0;
    if (frame.density_stats.active_voxels == 0 || voxels > double(1 << 22)) return;
    const vdb::DenseVolume dense = vdb::toDense(frame);
    if (dense.density.size() != dense.voxelCount() || dense.temperature.size() != dense.voxelCount())
        fuzz::fail(kTarget, "dense arrays differ from dims");
    for (std::size_t i = 0; i < dense.density.size(); ++i)
        if (!std::isfinite(dense.density[i]) || dense.density[i] < 0.0f || !std::isfinite(dense.temperature[i]))
            fuzz::fail(kTarget, "dense volume holds a non-finite value or a negative density");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::filesystem::path folder = fuzz::scratchFolder() / "sequence";
    std::filesystem::create_directories(folder);
    fuzz::writeBytes(folder / kFileName, data, size);
    try {
        const vdb::VdbSequence sequence = vdb::VdbSequence::open(folder.string());
        for (const vdb::FrameFile& file : sequence.frames()) checkFrame(sequence.load(file.number));
    } catch (const vdb::VdbError& e) {
        checkNamesFile(e);
    }
    return 0;
}
