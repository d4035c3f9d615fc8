#include "atomic_file.h"

#include <cstdint>
#include <random>
#include <sstream>
#include <system_error>

#include "image/image.h"

namespace firelook::image::detail {
namespace {

// Hidden and unique, so concurrent writers to one folder never collide and a listing skips it.
std::filesystem::path temporaryPathBeside(const std::filesystem::path& target) {
    std::random_device entropy;
    const std::uint64_t token = (static_cast<std::uint64_t>(entropy()) << 32) ^ entropy();
    std::ostringstream name;
    name << '.' << target.filename().string() << ".tmp-" << std::hex << token;
    return target.parent_path() / name.str();
}

}  // namespace

void writeAtomically(const std::filesystem::path& target,
                     const std::function<void(const std::filesystem::path& temporary)>& write_to) {
    const std::filesystem::path temporary = temporaryPathBeside(target);
    try {
        write_to(temporary);
        std::error_code error;
        std::filesystem::rename(temporary, target, error);
        if (error) {
            throw ImageError(target.string() +
                             ": cannot move the finished image into place: " + error.message());
        }
    } catch (...) {
        std::error_code ignored;  // best effort: the original error is the one worth reporting
        std::filesystem::remove(temporary, ignored);
        throw;
    }
}

}  // namespace firelook::image::detail
