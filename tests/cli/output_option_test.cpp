// docs/cli.md: every command that writes a file or folder names it with -o or --out, and the older
// spellings (bake's and repack's --output, animate's --out-dir, bench's --json) still work. Each
// case runs one command with one spelling on the tiny data of cli_test.cpp (frame 1 of the sample,
// 16x16, a few thousand photons; the package the commands read is baked once per test process).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "../support/command.h"
#include "../support/sample.h"
#include "../support/temp_dir.h"
#include "../support/tiny_bake_config.h"

namespace {

using namespace firelook::testing;  // TempDir, runIn, runFirelook, kTinyBakeConfig

using firelook::testing::kSample;

struct Writer {
    std::string command;  // `firelook` arguments, run in a folder inside the suite's; the output
                          // option and `output` are appended
    std::string output;   // what it writes, in the folder it runs in
    bool folder = false;
};

struct OutputCase {
    std::string name;  // the command and the spelling, for the test's name
    Writer writer;
    std::string flag;
};
// For gtest's messages: the name, not the bytes.
void PrintTo(const OutputCase& c, std::ostream* os) { *os << c.name; }

// Every command that writes a file or folder, and the spellings of its output option. "../" is the
// suite's folder, which holds bake.json, pkg.firelook and look.json.
std::vector<OutputCase> cases() {
    const std::vector<std::pair<Writer, std::vector<std::string>>> writers = {
        {{"bake '" + kSample + "' --frames 1 --size 16x16 --up z --config ../bake.json", "out.firelook"},
         {"-o", "--out", "--output"}},
        {{"render ../pkg.firelook --frame 1", "out.png"}, {"-o", "--out"}},
        {{"reference '" + kSample + "' --frame 1 --size 8x8 --spp 1 --up z", "out.exr"}, {"-o", "--out"}},
        {{"animate ../pkg.firelook --key 1:../look.json", "frames", true}, {"-o", "--out", "--out-dir"}},
        {{"repack ../pkg.firelook", "out.firelook"}, {"-o", "--out", "--output"}},
        {{"bench '" + kSample + "' --package ../pkg.firelook --frames 1 --looks 1 --spp 1 --alpha-rays 1", "out.json"},
         {"-o", "--out", "--json"}},
        {{"export-cycles ../pkg.firelook --frame 1 --sequence '" + kSample + "'", "out.py"}, {"-o", "--out"}},
    };
    std::vector<OutputCase> out;
    for (const auto& [writer, flags] : writers)
        for (const std::string& flag : flags) {
            std::string name = writer.command.substr(0, writer.command.find(' ')) + "_" +
                               flag.substr(flag.find_first_not_of('-'));
            for (char& c : name)
                if (c == '-') c = '_';
            out.push_back({name, writer, flag});
        }
    return out;
}

// The package and look every command but bake reads, made once for the suite; each case runs in
// its own folder inside the suite's.
class OutputOption : public ::testing::TestWithParam<OutputCase> {
  protected:
    static void SetUpTestSuite() {
        shared_ = std::make_unique<TempDir>();
        std::ofstream(*shared_ / "bake.json") << kTinyBakeConfig;
        const CommandResult bake =
            runFirelook(*shared_, "bake '" + kSample + "' -o pkg.firelook --frames 1 --size 16x16 --up z --config bake.json");
        ASSERT_EQ(bake.exit_code, 0) << bake.out << bake.err;
        const CommandResult info = runFirelook(*shared_, "info --json pkg.firelook");
        ASSERT_EQ(info.exit_code, 0) << info.err;
        std::ofstream(*shared_ / "look.json")
            << nlohmann::json::parse(info.out).at("metadata").at("bake").at("default_look").dump();
    }
    static void TearDownTestSuite() { shared_.reset(); }

    static std::unique_ptr<TempDir> shared_;
};
std::unique_ptr<TempDir> OutputOption::shared_;

TEST_P(OutputOption, WritesWhereTheOptionSays) {
    ASSERT_TRUE(shared_ && std::filesystem::exists(*shared_ / "pkg.firelook")) << "the suite's bake failed";
    const OutputCase& c = GetParam();
    const std::filesystem::path dir = *shared_ / c.name;
    ASSERT_TRUE(std::filesystem::create_directory(dir)) << dir;
    const CommandResult r =
        runIn(dir, "'" FIRELOOK_EXE "' " + c.writer.command + " " + c.flag + " " + c.writer.output);
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    const std::filesystem::path written = dir / c.writer.output;
    if (c.writer.folder) {
        EXPECT_TRUE(std::filesystem::is_regular_file(written / "frame_0001.png")) << written;
        EXPECT_TRUE(std::filesystem::is_regular_file(written / "contact_sheet.png")) << written;
    } else {
        ASSERT_TRUE(std::filesystem::is_regular_file(written)) << written;
        EXPECT_GT(std::filesystem::file_size(written), 0u) << written;
    }
    std::vector<std::string> entries;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) entries.push_back(entry.path().filename());
    EXPECT_EQ(entries, std::vector<std::string>{c.writer.output}) << "written there and nowhere else";
}

INSTANTIATE_TEST_SUITE_P(EveryWriter, OutputOption, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<OutputCase>& info) { return info.param.name; });

// Each spelling is listed, with -o and --out, in its command's --help.
TEST(OutputOptionHelp, ListsEverySpelling) {
    TempDir dir;
    for (const OutputCase& c : cases()) {
        const std::string command = c.writer.command.substr(0, c.writer.command.find(' '));
        const CommandResult r = runFirelook(dir, command + " --help");
        ASSERT_EQ(r.exit_code, 0) << command << ": " << r.err;
        EXPECT_NE(r.out.find("-o,--out"), std::string::npos) << command << ": " << r.out;
        EXPECT_NE(r.out.find(c.flag), std::string::npos) << c.flag << " missing from: " << r.out;
    }
}

}  // namespace
