#pragma once
// Internal to firelook::vdb: reading one file, without OpenVDB in this header.

#include <filesystem>
#include <string>
#include <vector>

#include "vdb/bounds.h"
#include "vdb/frame_files.h"
#include "vdb/read_options.h"
#include "vdb/volume_frame.h"

namespace firelook::vdb {

// Names of the grids in a VDB file, as OpenVDB lists them (sorted by name).
std::vector<std::string> listGridNames(const std::filesystem::path& file);

// Checks the file holds the two (resolved) grids as float grids and returns the density's
// interpolation support in world space, from metadata only when the file records the grid's
// active bounding box (OpenVDB's file_bbox_min/max), otherwise by reading the density grid.
Aabb readDensitySupportBounds(const std::filesystem::path& file, const ReadOptions& resolved);

// Reads, checks and cleans one frame; see VdbSequence::load.
VolumeFrame loadFrame(const FrameFile& frame, const ReadOptions& resolved);

}  // namespace firelook::vdb
