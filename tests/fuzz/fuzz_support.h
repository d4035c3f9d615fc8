// Shared by the fuzz entry points (tests/fuzz/README.md): a per-process scratch folder and a check
// that reports a broken invariant loudly. libFuzzer runs the entry points in process, so nothing
// here may leak or keep state that changes the next input's behaviour.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

namespace firelook::fuzz {

// A folder of this process (pid), made once and emptied by the callers' overwrites; removed at exit.
inline const std::filesystem::path& scratchFolder() {
    static const std::filesystem::path folder = [] {
        auto path = std::filesystem::temp_directory_path() / ("firelook-fuzz-" + std::to_string(::getpid()));
        std::filesystem::create_directories(path);
        std::atexit([] {
            std::error_code ignored;
            std::filesystem::remove_all(std::filesystem::temp_directory_path() /
                                            ("firelook-fuzz-" + std::to_string(::getpid())),
                                        ignored);
        });
        return path;
    }();
    return folder;
}

inline void writeBytes(const std::filesystem::path& file, const void* data, std::size_t size) {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
}

// A broken contract: printed, then abort() so that libFuzzer and the corpus replay both fail.
[[noreturn]] inline void fail(const char* target, const std::string& what) {
    std::fprintf(stderr, "\n*** %s: contract violated: %s\n", target, what.c_str());
    std::fflush(stderr);
    std::abort();
}

inline bool contains(std::string_view text, std::string_view part) { return text.find(part) != std::string_view::npos; }

}  // namespace firelook::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);
