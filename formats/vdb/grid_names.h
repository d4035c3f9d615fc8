#pragma once
// Internal to firelook::vdb: choosing and finding grids by name.

#include <filesystem>
#include <string>
#include <vector>

#include "vdb/read_options.h"

namespace firelook::vdb {

// Fills empty grid names in `options` from the grids of `file` (the first frame): density from
// "density"; temperature from "temperature", then "heat", then "flame". Throws VdbError naming the
// file and listing its grids when no candidate is present.
void resolveGridNames(ReadOptions& options, const std::vector<std::string>& grids_in_file,
                      const std::filesystem::path& file);

// Throws VdbError naming the file and listing its grids unless `grid` is among them; `role` is
// "density" or "temperature".
void requireGrid(const std::vector<std::string>& grids_in_file, const std::string& grid,
                 const std::string& role, const std::filesystem::path& file);

}  // namespace firelook::vdb
