#include "cli/atomic_write.h"

#include <fstream>
#include <stdexcept>
#include <system_error>

namespace firelook::cli {

void writeFileAtomically(const std::filesystem::path& target, std::string_view bytes) {
    const std::filesystem::path temporary = target.string() + ".tmp";
    std::error_code ignored;
    {
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        out.close();
        if (!out) {
            std::filesystem::remove(temporary, ignored);
            throw std::runtime_error(target.string() + ": cannot write the file");
        }
    }
    std::error_code error;
    std::filesystem::rename(temporary, target, error);
    if (error) {
        std::filesystem::remove(temporary, ignored);
        throw std::runtime_error(target.string() + ": cannot move the finished file into place: " + error.message());
    }
}

}  // namespace firelook::cli
