#include "text_file.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "common/atomic_file.h"
#include "common/error.h"
#include "fl_check.h"

namespace firelook::viewer {

std::string readTextFile(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw ViewerError("cannot read " + path.string() + ": " + std::strerror(errno));
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw ViewerError("error reading " + path.string());
    return text.str();
}

void writeTextFileAtomic(const std::filesystem::path& path, const std::string& text) {
    try {
        writeFileAtomically(path, text);
    } catch (const Error& error) {
        throw ViewerError(error.what());  // "<path>: cannot ..."
    }
}

}  // namespace firelook::viewer
