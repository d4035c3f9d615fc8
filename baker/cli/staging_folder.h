// All-or-nothing output folders (animate, flipbook): the files go into a hidden folder inside the
// output folder and are moved into place only once every one is complete, so an error or an
// interrupt leaves the output folder as it was (one created by the run is removed).
#pragma once

#include <filesystem>
#include <string>

namespace firelook::cli {

// A hidden folder in the output folder that holds the files until they are all written; removed
// (with the output folder itself, if this run created it) unless commit() moved everything out.
class StagingFolder {
  public:
    // `command` names the hidden folder (".firelook-COMMAND-PID-N").
    StagingFolder(const std::filesystem::path& out_dir, const std::string& command);
    ~StagingFolder();
    StagingFolder(const StagingFolder&) = delete;
    StagingFolder& operator=(const StagingFolder&) = delete;

    std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

    // Moves every staged file over its namesake in the output folder (renames: no more writing).
    void commit();

  private:
    std::filesystem::path out_dir_, path_;
    bool created_out_dir_ = false, committed_ = false;
};

}  // namespace firelook::cli
