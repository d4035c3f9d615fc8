#include "grid_names.h"

#include <algorithm>

#include "vdb/vdb_error.h"

namespace firelook::vdb {
namespace {

bool contains(const std::vector<std::string>& names, const std::string& name) {
    return std::find(names.begin(), names.end(), name) != names.end();
}

std::string listOf(const std::vector<std::string>& names) {
    if (names.empty()) return "none";
    std::string list;
    for (const std::string& name : names) list += (list.empty() ? "'" : ", '") + name + "'";
    return list;
}

std::string firstPresent(const std::vector<std::string>& candidates,
                         const std::vector<std::string>& grids_in_file, const std::string& role,
                         const std::filesystem::path& file) {
    for (const std::string& candidate : candidates) {
        if (contains(grids_in_file, candidate)) return candidate;
    }
    throw VdbError(file.string() + ": no " + role + " grid found (looked for " + listOf(candidates) +
                   "; grids in file: " + listOf(grids_in_file) + "); name it in the read options");
}

}  // namespace

void resolveGridNames(ReadOptions& options, const std::vector<std::string>& grids_in_file,
                      const std::filesystem::path& file) {
    if (options.density_grid.empty()) {
        options.density_grid = firstPresent({"density"}, grids_in_file, "density", file);
    }
    if (options.temperature_grid.empty()) {
        options.temperature_grid =
            firstPresent({"temperature", "heat", "flame"}, grids_in_file, "temperature", file);
    }
}

void requireGrid(const std::vector<std::string>& grids_in_file, const std::string& grid,
                 const std::string& role, const std::filesystem::path& file) {
    if (!contains(grids_in_file, grid)) {
        throw VdbError(file.string() + ": " + role + " grid '" + grid +
                       "' not found (grids in file: " + listOf(grids_in_file) + ")");
    }
}

}  // namespace firelook::vdb
