// How a package's sequence was read, from the "provenance" its bake recorded (bake_pipeline.cpp,
// sharedMetadata): the grids, the temperature and density mappings and --clamp-extreme, so that a
// reference traces the very data the bake saw.
#pragma once

#include <string>

#include "vdb/read_options.h"

namespace firelook::reference {

// metadata_json: the package's metadata document (basis::BasisReader::metadataJson,
// fl_package_get_metadata_json). density_grid, temperature_grid, temperature_scale and
// temperature_offset are required (every bake records them); density_scale (recorded only when
// not 1) defaults to 1 and clamp_extreme to false. The policies and callbacks (strict, warn,
// before_load) are left at their defaults for the caller. Throws firelook::Error naming
// package_name and the problem: ErrorCode::Corrupt for a document that is not JSON or a value of
// the wrong type, ErrorCode::NotFound for a missing provenance or entry.
vdb::ReadOptions provenanceReadOptions(const std::string& metadata_json, const std::string& package_name);

}  // namespace firelook::reference
