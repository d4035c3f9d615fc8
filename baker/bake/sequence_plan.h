// What a bake needs from the whole sequence, gathered in one pass over every frame: the content
// hash of each frame's file (the sequence's identity, whatever path it is read from), the world
// bounds the default camera frames, and the survey the temperature bins, the derived axes and the
// axis collapse come from. A bake makes it first; `firelook bake --plan-only` writes it as a plan
// file and `bake --plan` reads it back, so each shard of a farm reads only its own frames
// (docs/cli.md, "Shards, merge and resume").
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "bake/axis_collapse.h"
#include "bake/axis_derivation.h"
#include "render/medium.h"
#include "vdb/vdb_sequence.h"

namespace firelook::bake {

// What one pass over every frame of the whole sequence (never only the selected frames, so that
// shards agree) measures for the axes: the temperatures where there is density (the axis collapse),
// the density statistic the extinction axes are derived from, and the temperature range the bins
// span (scene_setup.h, TemperatureSpan).
struct SequenceSurvey {
    DensityTemperatureRange temperatures;
    DensityDepth density;
    std::pair<double, double> temperature_range{0.0, 1.0};
};
SequenceSurvey surveySequence(const vdb::VdbSequence& sequence,
                              const std::function<bool(int frame)>& keep_going = {});

struct PlannedFrame {
    int number = 0;
    std::string file;     // its file name (no folder: the same files anywhere plan alike)
    std::string xxh3_64;  // of the file's bytes, 16 hex digits (`xxhsum -H3 FILE`)
};

struct SequencePlan {
    std::vector<PlannedFrame> frames;  // every frame of the sequence, ascending
    // XXH3-64 of the frames' numbers and hashes: META's provenance.sequence_xxh3_64, what `merge`
    // compares first to tell parts of another sequence.
    std::string sequence_xxh3_64;
    // The read settings the survey depends on: grid names as resolved, temperature and density
    // mapping, clamp_extreme.
    vdb::ReadOptions read;
    vdb::Aabb world_bounds;
    SequenceSurvey survey;
    const PlannedFrame* find(int number) const;
};

// XXH3-64 as 16 hex digits: of a text, and of a file's bytes (an Error naming the file when it
// cannot be read). XXH3 is the hash the package's section checksums already use; 64 bits make an
// accidental match of two different frames negligible (no adversary is assumed).
std::string xxh3Hex(const std::string& text);
std::string fileXxh3(const std::filesystem::path& file);

// A frame's medium as a bake traces it and what the package records of its read (META's
// "source"), from one read of its file.
struct LoadedFrame {
    int number = -1;  // -1: none
    std::string file;  // the file's name
    std::uint64_t cleaned_non_finite = 0, cleaned_negative_density = 0, clamped_extreme = 0, active_voxels = 0;
    render::Medium medium;
};
LoadedFrame loadFrame(const vdb::VolumeFrame& frame);

// Reads every frame once: its hash, and the survey. keep_going(frame) false cancels (throws). With
// `kept`, the frame numbered `keep` is kept as it was read there (a bake's first frame to trace:
// its file is then not read and made dense a second time, about 0.8 s of a 33-million-voxel frame).
SequencePlan planSequence(const vdb::VdbSequence& sequence,
                          const std::function<bool(int frame)>& keep_going = {}, int keep = -1,
                          LoadedFrame* kept = nullptr);

// The plan file: JSON with every number written to round-trip exactly, so a bake from the file
// writes the bytes of a bake that surveyed the sequence itself. `sequence_path` is recorded as
// typed, for people; nothing compares it.
std::string planToJson(const SequencePlan& plan, const std::string& sequence_path);
// Throws a Corrupt Error naming `file` when the text is not a plan of this version.
SequencePlan planFromJson(const std::string& text, const std::filesystem::path& file);

// The read options a bake from `plan` uses: `requested` with the plan's grid names where it names
// none. Throws an InvalidArgument Error naming `plan_file` and the first setting that differs from
// what the plan was made with.
vdb::ReadOptions plannedReadOptions(const SequencePlan& plan, vdb::ReadOptions requested,
                                    const std::filesystem::path& plan_file);

// Throws an InvalidArgument Error naming `plan_file` when the sequence's files (numbers and names)
// are not the plan's: the plan was made from another sequence or before frames were added or removed.
void checkPlanFiles(const SequencePlan& plan, const vdb::VdbSequence& sequence,
                    const std::filesystem::path& plan_file);

}  // namespace firelook::bake
