#include "vdb/frame_files.h"

#include <algorithm>
#include <cctype>
#include <optional>
#include <set>
#include <system_error>

#include "vdb/vdb_error.h"

namespace firelook::vdb {
namespace {

namespace fs = std::filesystem;

// Frame numbers are ints; nine digits always fit.
constexpr std::size_t kMaxFrameDigits = 9;

bool isDigit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }

bool hasVdbExtension(const fs::path& path) { return path.extension() == ".vdb"; }

// The file-name template of a pattern: literal text around one frame field.
struct NamePattern {
    std::string prefix, suffix;
    std::size_t padding = 0;  // minimum digits; 0 = any number of digits, no padding
};

// Parses "fire_####.vdb", "fire_%04d.vdb" or "fire_%d.vdb"; nullopt if the name has no frame field.
std::optional<NamePattern> parseNamePattern(const std::string& name, const std::string& source) {
    std::optional<NamePattern> pattern;
    std::size_t field_begin = 0, field_end = 0;
    for (std::size_t i = 0; i < name.size();) {
        std::size_t end = i;
        std::size_t padding = 0;
        if (name[i] == '#') {
            while (end < name.size() && name[end] == '#') ++end;
            padding = end - i;
        } else if (name[i] == '%') {
            end = i + 1;
            while (end < name.size() && isDigit(name[end])) ++end;
            if (end >= name.size() || name[end] != 'd') {
                throw VdbError(source + ": unsupported '%' field in pattern (use %d, %0Nd or ####)");
            }
            const std::string width = name.substr(i + 1, end - i - 1);
            padding = width.empty() ? 0 : std::stoul(width);
            ++end;
        } else {
            ++i;
            continue;
        }
        if (pattern) throw VdbError(source + ": pattern has more than one frame field");
        pattern = NamePattern{};
        pattern->padding = padding;
        field_begin = i;
        field_end = end;
        i = end;
    }
    if (pattern) {
        pattern->prefix = name.substr(0, field_begin);
        pattern->suffix = name.substr(field_end);
    }
    return pattern;
}

// The frame number `digits` stands for in a field of the given padding, if it is one: exactly
// `padding` digits, or more with no leading zero (a number too big for the padding).
std::optional<int> frameNumberFromField(const std::string& digits, std::size_t padding) {
    if (digits.empty() || digits.size() > kMaxFrameDigits) return std::nullopt;
    if (!std::all_of(digits.begin(), digits.end(), isDigit)) return std::nullopt;
    if (padding > 0 && digits.size() < padding) return std::nullopt;
    if (padding > 0 && digits.size() > padding && digits[0] == '0') return std::nullopt;
    return std::stoi(digits);
}

// Splits a file stem into the prefix and the digits that end it ("fluid_data_0012" -> "fluid_data_", 12).
struct StemParts {
    std::string prefix;
    std::optional<int> number;
};

StemParts splitStem(const std::string& stem) {
    std::size_t digits_begin = stem.size();
    while (digits_begin > 0 && isDigit(stem[digits_begin - 1])) --digits_begin;
    const std::string digits = stem.substr(digits_begin);
    if (digits.empty() || digits.size() > kMaxFrameDigits) return {stem, std::nullopt};
    return {stem.substr(0, digits_begin), std::stoi(digits)};
}

std::vector<fs::path> regularFilesIn(const fs::path& folder, const std::string& source) {
    std::vector<fs::path> files;
    std::error_code error;
    for (fs::directory_iterator it(folder, error), end; !error && it != end; it.increment(error)) {
        if (it->is_regular_file(error)) files.push_back(it->path());
    }
    if (error) throw VdbError(ErrorCode::IoError, source + ": cannot list folder: " + error.message());
    return files;
}

std::string quotedList(const std::set<std::string>& names) {
    std::string list;
    for (const std::string& name : names) list += (list.empty() ? "'" : ", '") + name + "'";
    return list;
}

// Sorts by number and refuses two files with one number (e.g. fire_01.vdb and fire_001.vdb).
std::vector<FrameFile> sortedUnique(std::vector<FrameFile> frames, const std::string& source) {
    std::sort(frames.begin(), frames.end(),
              [](const FrameFile& a, const FrameFile& b) { return a.number < b.number; });
    for (std::size_t i = 1; i < frames.size(); ++i) {
        if (frames[i].number == frames[i - 1].number) {
            throw VdbError(source + ": files " + frames[i - 1].path.string() + " and " +
                           frames[i].path.string() + " are both frame " + std::to_string(frames[i].number));
        }
    }
    return frames;
}

std::vector<FrameFile> framesInFolder(const fs::path& folder, const std::string& source) {
    std::vector<FrameFile> frames;
    std::set<std::string> prefixes;
    for (const fs::path& file : regularFilesIn(folder, source)) {
        if (!hasVdbExtension(file)) continue;
        const StemParts parts = splitStem(file.stem().string());
        if (!parts.number) {
            throw VdbError(source + ": " + file.filename().string() +
                           " has no frame number at the end of its name");
        }
        prefixes.insert(parts.prefix);
        frames.push_back({*parts.number, file});
    }
    if (frames.empty()) throw VdbError(source + ": folder holds no .vdb file");
    if (prefixes.size() > 1) {
        throw VdbError(source +
                       ": folder mixes sequences with different name prefixes: " + quotedList(prefixes));
    }
    return sortedUnique(std::move(frames), source);
}

std::vector<FrameFile> framesMatching(const fs::path& folder, const NamePattern& pattern,
                                      const std::string& source) {
    if (!fs::is_directory(folder))
        throw VdbError(ErrorCode::IoError, source + ": folder " + folder.string() + " does not exist");
    std::vector<FrameFile> frames;
    for (const fs::path& file : regularFilesIn(folder, source)) {
        const std::string name = file.filename().string();
        if (name.size() <= pattern.prefix.size() + pattern.suffix.size()) continue;
        if (!name.starts_with(pattern.prefix) || !name.ends_with(pattern.suffix)) continue;
        const std::string field =
            name.substr(pattern.prefix.size(), name.size() - pattern.prefix.size() - pattern.suffix.size());
        if (const std::optional<int> number = frameNumberFromField(field, pattern.padding)) {
            frames.push_back({*number, file});
        }
    }
    if (frames.empty()) throw VdbError(source + ": no file matches the pattern");
    return sortedUnique(std::move(frames), source);
}

}  // namespace

std::vector<FrameFile> findFrameFiles(const std::string& folder_or_pattern) {
    const std::string& source = folder_or_pattern;
    const fs::path path(folder_or_pattern);
    if (fs::is_directory(path)) return framesInFolder(path, source);
    const std::optional<NamePattern> pattern = parseNamePattern(path.filename().string(), source);
    if (pattern) {
        const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
        return framesMatching(folder, *pattern, source);
    }
    if (fs::is_regular_file(path)) return {{splitStem(path.stem().string()).number.value_or(0), path}};
    throw VdbError(ErrorCode::IoError,
                   source +
                       ": no such folder or file, and not a pattern (use a folder, fire_####.vdb or "
                       "fire_%04d.vdb)");
}

std::vector<int> missingFrameNumbers(const std::vector<FrameFile>& frames) {
    std::vector<int> missing;
    for (std::size_t i = 1; i < frames.size(); ++i) {
        for (int number = frames[i - 1].number + 1; number < frames[i].number; ++number)
            missing.push_back(number);
    }
    return missing;
}

std::string formatFrameNumbers(const std::vector<int>& numbers) {
    std::string text;
    for (std::size_t i = 0; i < numbers.size();) {
        std::size_t j = i;
        while (j + 1 < numbers.size() && numbers[j + 1] == numbers[j] + 1) ++j;
        text += (text.empty() ? "" : ", ") + std::to_string(numbers[i]);
        if (j > i) text += "-" + std::to_string(numbers[j]);
        i = j + 1;
    }
    return text;
}

std::string describeMissingFrames(const std::vector<int>& numbers) {
    return (numbers.size() == 1 ? "frame " : "frames ") + formatFrameNumbers(numbers) + " missing";
}

}  // namespace firelook::vdb
