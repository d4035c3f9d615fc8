// `firelook merge`, and the last step of every bake: one package from packages that each hold
// some frames of one bake (shards baked on several machines, or the per-frame parts a bake keeps
// while it runs, bake/bake_checkpoint.h).
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace firelook::bake {

struct MergeOptions {
    // Accept frames of the sequence missing between the first and the last frame the parts hold.
    bool allow_gaps = false;
    // Write only the parts' frames in these [first, last] ranges (`firelook split`); empty: all.
    std::vector<std::pair<int, int>> only;
};

struct MergeResult {
    std::vector<int> frames;  // in the order written (increasing)
    uint64_t package_bytes = 0;
};

// Checks that `parts` were baked from one sequence with the same settings (the same package format
// and the same metadata apart from each frame's own entries, bake/bake_metadata.h), that no frame
// is in two parts and, unless options.allow_gaps, that no frame of the sequence between the first
// and the last frame present is missing. Then writes `output` atomically with the frames in
// increasing order, every section copied as stored: byte for byte the package that one bake of
// those frames writes. Throws firelook::Error naming the part and the problem (nothing is
// written then; also when `options.only` selects no frame). `notice` gets one line per part read.
MergeResult mergePackages(const std::vector<std::filesystem::path>& parts, const std::filesystem::path& output,
                          const MergeOptions& options = {},
                          const std::function<void(const std::string&)>& notice = {});

}  // namespace firelook::bake
