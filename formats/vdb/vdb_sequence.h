#pragma once

#include <string>
#include <vector>

#include "vdb/bounds.h"
#include "vdb/dense_volume.h"
#include "vdb/frame_files.h"
#include "vdb/read_options.h"
#include "vdb/vdb_error.h"
#include "vdb/volume_frame.h"

namespace firelook::vdb {

// A sequence of OpenVDB files holding a density and a temperature grid per frame (docs/model.md
// and docs/cli.md, "Sequences"). Opening reads only the grid metadata of every file (no
// voxel data): it resolves the grid names, checks every file holds both grids as float grids,
// and computes the sequence-wide bounds. load() reads one frame's voxels. The object is immutable
// after open(), so load() may be called from several threads at once.
class VdbSequence {
  public:
    // Throws VdbError naming the file or pattern on any problem (see findFrameFiles for the
    // accepted forms; a file that is not VDB, a missing grid, a non-float grid). Gaps in the frame
    // numbers go to options.warn ("SOURCE: frames 3, 5-7 missing"), or throw under options.strict.
    static VdbSequence open(const std::string& folder_or_pattern, ReadOptions options = {});
    // The same sequence when its grid names (in `options`) and world bounds are already known, from
    // a plan made by reading every frame once (baker/bake/sequence_plan.h): only the folder is
    // listed, so no file is read until load(), and a frame that cannot be read fails only the
    // process that loads it. Throws VdbError as open() does for the file names and the gaps, and
    // when `options` does not name both grids.
    static VdbSequence openKnown(const std::string& folder_or_pattern, ReadOptions options, const Aabb& world_bounds);

    const std::string& source() const { return source_; }
    const std::vector<FrameFile>& frames() const { return frames_; }
    // Frame numbers missing between the first and the last frame (allowed, but worth reporting).
    std::vector<int> gaps() const { return missingFrameNumbers(frames_); }
    bool hasFrame(int frame_number) const;

    // Reads, checks and cleans one frame (see VolumeFrame for what it holds). Throws VdbError
    // naming the file for: a frame number not in the sequence, a missing or non-float grid (the
    // message lists the grids present), grids with different transforms, a non-linear transform,
    // a non-zero density background, and, under NonFinitePolicy::Refuse, NaN/Inf values or
    // negative densities (the message gives their count), a value beyond the plausible range
    // without clamp_extreme (the message names the grid, the value and the voxel; read_options.h),
    // and under strict any value that would be cleaned or clamped. What was cleaned or clamped goes
    // to options.warn, one line per grid (cleaningReport).
    VolumeFrame load(int frame_number) const;

    // Union of every frame's world_bounds (computed from the per-grid bounding boxes OpenVDB
    // stores in the file metadata, falling back to reading the grid when they are absent).
    // Empty only if no frame has an active density voxel.
    const Aabb& sequenceWorldBounds() const { return world_bounds_; }

    // The options in use, with density_grid and temperature_grid holding the resolved names.
    const ReadOptions& options() const { return options_; }

  private:
    VdbSequence() = default;

    std::string source_;
    std::vector<FrameFile> frames_;
    ReadOptions options_;
    Aabb world_bounds_;
};

}  // namespace firelook::vdb
