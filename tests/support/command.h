// Running a program through the shell from a test, and reading what it wrote. The command runs in
// a folder of the test's choosing; its stdout and stderr go to files in a private TempDir (never
// the folder under test, so they never show up in the listings a test checks), and come back as
// strings. Shared by every test suite (included as "../support/command.h").
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "temp_dir.h"

namespace firelook::testing {

// The whole file as bytes; empty when it cannot be read.
inline std::string readFile(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

// The non-empty lines of `text`.
inline std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);)
        if (!line.empty()) out.push_back(line);
    return out;
}

struct CommandResult {
    int exit_code = -1;  // the exit status, or 128 + the signal that killed the command (as a shell says)
    std::string out, err;
};

// Runs `command` through the shell with `folder` as the working folder and stdin from /dev/null;
// the command is passed to the shell as written.
inline CommandResult runIn(const std::filesystem::path& folder, const std::string& command) {
    const TempDir logs;
    const std::string line = "cd '" + folder.string() + "' && " + command + " > '" + (logs / "out").string() +
                             "' 2> '" + (logs / "err").string() + "' < /dev/null";
    const int status = std::system(line.c_str());
    CommandResult r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.out = readFile(logs / "out");
    r.err = readFile(logs / "err");
    return r;
}

inline CommandResult runIn(const TempDir& folder, const std::string& command) {
    return runIn(folder.path(), command);
}

#ifdef FIRELOOK_EXE
// Runs `firelook <args>` in `folder` (FIRELOOK_EXE: the executable, defined by the test target).
inline CommandResult runFirelook(const TempDir& folder, const std::string& args) {
    return runIn(folder, "'" FIRELOOK_EXE "' " + args);
}
#endif

}  // namespace firelook::testing
