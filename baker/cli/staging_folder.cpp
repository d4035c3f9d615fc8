#include "cli/staging_folder.h"

#include <unistd.h>

#include <system_error>

namespace firelook::cli {

StagingFolder::StagingFolder(const std::filesystem::path& out_dir, const std::string& command) : out_dir_(out_dir) {
    created_out_dir_ = std::filesystem::create_directories(out_dir_);
    for (unsigned n = 0;; ++n) {
        path_ = out_dir_ / (".firelook-" + command + "-" + std::to_string(::getpid()) + "-" + std::to_string(n));
        if (std::filesystem::create_directory(path_)) break;
    }
}

StagingFolder::~StagingFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
    if (!committed_ && created_out_dir_) std::filesystem::remove(out_dir_, ignored);  // only if empty
}

void StagingFolder::commit() {
    for (const auto& entry : std::filesystem::directory_iterator(path_))
        std::filesystem::rename(entry.path(), out_dir_ / entry.path().filename());
    committed_ = true;
}

}  // namespace firelook::cli
