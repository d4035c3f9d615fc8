#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace firelook::vdb {

struct FrameFile {
    int number = 0;
    std::filesystem::path path;
};

// Finds the files of a sequence, sorted by frame number. folder_or_pattern is one of:
// - a folder: every *.vdb file in it; all must be <prefix><digits>.vdb with one common prefix;
// - a pattern whose file name holds one frame field: a run of '#' (that many zero-padded digits;
//   a frame needing more digits is written unpadded) or printf's %d / %0Nd, e.g. fire_####.vdb;
// - one existing file: a one-frame sequence numbered by the digits ending its name (0 if none).
// Throws VdbError naming the folder or pattern when nothing matches, when file names in a folder
// have different prefixes (they are listed), or when two files give the same frame number.
std::vector<FrameFile> findFrameFiles(const std::string& folder_or_pattern);

// Frame numbers missing between the first and the last frame, ascending.
std::vector<int> missingFrameNumbers(const std::vector<FrameFile>& frames);

// Ascending frame numbers with runs written as ranges: {3, 5, 6, 7} -> "3, 5-7".
std::string formatFrameNumbers(const std::vector<int>& numbers);

// "frame 3 missing" or "frames 3, 5-7 missing" (the words of the gap warning).
std::string describeMissingFrames(const std::vector<int>& numbers);

}  // namespace firelook::vdb
