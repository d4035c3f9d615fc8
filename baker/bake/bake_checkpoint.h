// The frames a bake has finished, kept beside its output as one small package each
// ("<output>.partial/frame_<n>.firelook", each written atomically), so that a bake stopped by
// Ctrl-C, a kill or a crash continues with `--resume` from the frames still missing. The package
// itself is assembled from these parts (bake/package_merge.h), so a resumed bake writes the same
// bytes as one that was never stopped.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "bake/bake_metadata.h"

namespace firelook::bake {

class BakeCheckpoint {
  public:
    // Creates the folder (not the output's folder: a missing one is an error, as for the package).
    // Without `resume`, parts an earlier bake left there are deleted first; with it they are kept,
    // and writers' temporary files (a killed write) are deleted.
    BakeCheckpoint(const std::filesystem::path& output, bool resume);
    // Removes the folder when it holds no finished part (a bake stopped before its first frame).
    ~BakeCheckpoint();
    BakeCheckpoint(const BakeCheckpoint&) = delete;
    BakeCheckpoint& operator=(const BakeCheckpoint&) = delete;

    static std::filesystem::path folderFor(const std::filesystem::path& output);
    const std::filesystem::path& folder() const { return folder_; }
    std::filesystem::path partPath(int frame) const;

    // The entries of the part kept for `frame` when it was baked exactly like this bake (`shared`,
    // the shared metadata, which holds the sequence's identity: every frame's file unchanged) from
    // an input file whose XXH3-64 is `source_hash`; otherwise nullopt, with the reason in `why`
    // ("" when there is no part): the frame's own file first, then another frame, then the settings.
    std::optional<FrameMetadata> reusable(int frame, const nlohmann::ordered_json& shared,
                                          const std::string& source_hash, std::string& why) const;

    // How many finished parts the folder of `output` holds (0 when there is none).
    static size_t keptFrames(const std::filesystem::path& output);

    // Deletes the folder (after the package is written).
    void remove();

  private:
    std::filesystem::path folder_;
};

}  // namespace firelook::bake
