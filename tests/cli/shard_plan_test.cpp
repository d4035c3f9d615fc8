// What real farms do (issue 32), end to end (docs/cli.md, "Shards, merge and resume"): a sequence
// is its frames' content, not the path it is typed as or mounted at; a shard baked with a plan
// (`bake --plan-only`, then `bake --plan`) reads only its own frames, so a broken frame elsewhere
// fails only the shard that holds it; merge names the sequence when a part is of another one; a
// usage error is one line. Bakes are tiny: 16x16 with the tiny settings, 2-3 frames of the sample.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "../support/command.h"
#include "../support/sample.h"
#include "../support/temp_dir.h"
#include "../support/tiny_bake_config.h"

namespace {

namespace fs = std::filesystem;
using namespace firelook::testing;  // TempDir, runFirelook, readFile, lines, kTinyBakeConfig
using nlohmann::json;

const std::string kShardSettings = " --size 16x16 --up z --config bake.json";

// dir/folder/fluid_data_000N.vdb for N in `frames`: the sample's frame `from[i]` as frame frames[i].
void copyFrames(const fs::path& folder, const std::vector<int>& frames, const std::vector<int>& from) {
    fs::create_directories(folder);
    const auto name = [](int n) { return "fluid_data_000" + std::to_string(n) + ".vdb"; };
    for (size_t i = 0; i < frames.size(); ++i)
        fs::copy_file(fs::path(kSample) / name(from[i]), folder / name(frames[i]));
}

// A failure: non-zero exit and one error line on stderr, the last, naming `mentions` (a bake's
// progress line may come before it).
void expectTheOneErrorLine(const CommandResult& r, const std::string& mentions) {
    EXPECT_NE(r.exit_code, 0) << r.out << r.err;
    const std::vector<std::string> err = lines(r.err);
    ASSERT_FALSE(err.empty()) << "no error message";
    EXPECT_EQ(std::count_if(err.begin(), err.end(),
                            [](const std::string& l) { return l.rfind("firelook: error: ", 0) == 0; }),
              1)
        << r.err;
    EXPECT_EQ(err.back().rfind("firelook: error: ", 0), 0u) << r.err;
    EXPECT_NE(err.back().find(mentions), std::string::npos) << "expected '" << mentions << "' in: " << r.err;
}

CommandResult bake(const TempDir& dir, const std::string& args) {
    return runFirelook(dir, "bake " + args + kShardSettings);
}

TEST(CliFarm, TheSameFilesUnderAnyPathBakeTheSameBytes) {
    TempDir dir;
    std::ofstream(dir / "bake.json") << kTinyBakeConfig;
    copyFrames(dir / "x" / "seq", {1, 2, 3}, {1, 2, 3});
    copyFrames(dir / "y" / "other", {1, 2, 3}, {1, 2, 3});
    const std::string elsewhere = "'" + (dir / "y" / "other" / "fluid_data_####.vdb").string() + "'";
    ASSERT_EQ(bake(dir, "x/seq -o typed.firelook --report typed.json").exit_code, 0);
    ASSERT_EQ(bake(dir, "./x/seq/ -o dotted.firelook").exit_code, 0);
    ASSERT_EQ(bake(dir, elsewhere + " -o elsewhere.firelook --report elsewhere.json").exit_code, 0);
    const std::string typed = readFile(dir / "typed.firelook");
    EXPECT_TRUE(readFile(dir / "dotted.firelook") == typed) << "seq and ./seq/ baked different bytes";
    EXPECT_TRUE(readFile(dir / "elsewhere.firelook") == typed)
        << "a copy at another path baked different bytes";
    // The path as typed stays in the bake's report, beside the identity the package records.
    const json typed_report = json::parse(readFile(dir / "typed.json"));
    const json elsewhere_report = json::parse(readFile(dir / "elsewhere.json"));
    EXPECT_EQ(typed_report.at("sequence"), "x/seq");
    EXPECT_EQ(elsewhere_report.at("sequence_xxh3_64"), typed_report.at("sequence_xxh3_64"));
    EXPECT_EQ(typed_report.at("sequence_xxh3_64").get<std::string>().size(), 16u);

    // Shards baked from the two copies, spelled differently, merge into the one-shot bytes.
    ASSERT_EQ(bake(dir, "x/seq --frames 1 -o a.firelook").exit_code, 0);
    ASSERT_EQ(bake(dir, elsewhere + " --frames 2-3 -o b.firelook").exit_code, 0);
    CommandResult r = runFirelook(dir, "merge a.firelook b.firelook -o merged.firelook");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(readFile(dir / "merged.firelook") == typed);

    // A sequence with the same frame numbers and other content: merge names the sequence, not the
    // first setting derived from it.
    copyFrames(dir / "z", {1, 2, 3}, {1, 4, 5});
    ASSERT_EQ(bake(dir, "z --frames 2-3 -o z.firelook").exit_code, 0);
    r = runFirelook(dir, "merge a.firelook z.firelook -o mixed.firelook");
    expectTheOneErrorLine(r, "z.firelook: baked from another sequence than a.firelook");
    EXPECT_NE(r.err.find("provenance.sequence_xxh3_64"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "mixed.firelook"));
}

TEST(CliFarm, AShardWithAPlanReadsOnlyItsFrames) {
    TempDir dir;
    std::ofstream(dir / "bake.json") << kTinyBakeConfig;
    copyFrames(dir / "seq", {1, 2, 3}, {1, 2, 3});
    ASSERT_EQ(bake(dir, "seq -o one.firelook").exit_code, 0);
    CommandResult r = runFirelook(dir, "bake seq --plan-only -o plan.json --config bake.json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("wrote plan.json: 3 frames (1-3)"), std::string::npos) << r.out;
    ASSERT_EQ(bake(dir, "seq --plan plan.json --frames 2-3 -o b.firelook").exit_code, 0);

    // Frame 2 becomes unreadable after the plan (a failed copy, a broken mount on one node).
    std::ofstream(dir / "seq" / "fluid_data_0002.vdb", std::ios::trunc) << "not a VDB file";
    r = bake(dir, "seq --frames 1 -o without-plan.firelook");
    EXPECT_NE(r.exit_code, 0) << "without a plan every frame is read, frame 2 too";
    EXPECT_NE(r.err.find("fluid_data_0002.vdb"), std::string::npos) << r.err;
    r = bake(dir, "seq --plan plan.json --frames 1 -o a.firelook");
    ASSERT_EQ(r.exit_code, 0) << "a shard whose frames are fine: " << r.err;
    r = runFirelook(dir, "merge b.firelook a.firelook -o merged.firelook");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(readFile(dir / "merged.firelook") == readFile(dir / "one.firelook"));
    // The shard that holds the frame fails, naming it.
    r = bake(dir, "seq --plan plan.json --frames 2 -o two.firelook");
    expectTheOneErrorLine(r, "fluid_data_0002.vdb: its content (xxh3 ");
    EXPECT_NE(r.err.find("since the plan was made"), std::string::npos) << r.err;

    // A plan is refused for a bake that reads the data otherwise, or for another folder.
    json scaled = json::parse(kTinyBakeConfig);
    scaled["density_scale"] = 2.0;
    std::ofstream(dir / "scaled.json") << scaled.dump();
    r = runFirelook(dir,
                    "bake seq --plan plan.json --frames 1 -o s.firelook --size 16x16 --config scaled.json");
    expectTheOneErrorLine(r, "plan.json: made with density_scale 1.0, this bake reads 2.0");
    copyFrames(dir / "four", {1, 2, 3, 4}, {1, 2, 3, 4});
    r = bake(dir, "four --plan plan.json --frames 1 -o f.firelook");
    expectTheOneErrorLine(r, "fluid_data_0004.vdb is not in the plan");
    EXPECT_FALSE(fs::exists(dir / "s.firelook"));
    EXPECT_FALSE(fs::exists(dir / "f.firelook"));
    EXPECT_FALSE(fs::exists(dir / "two.firelook"));
}

// docs/cli.md: every failure, a usage error too, is one line on stderr.
TEST(CliFarm, UsageErrorsAreOneLine) {
    TempDir dir;
    const std::vector<std::pair<std::string, std::string>> usage_errors = {
        {"bake '" + kSample + "' -o p.firelook --no-such-option", "--no-such-option"},
        {"bake '" + kSample + "' --plan-only --frames 1 -o plan.json", "--plan-only"},
        {"merge -o m.firelook", "PART"},
        {"no-such-command", "subcommand"}};
    for (const auto& [args, mentions] : usage_errors) {
        const CommandResult r = runFirelook(dir, args);
        expectTheOneErrorLine(r, mentions);
        EXPECT_EQ(lines(r.err).size(), 1u) << args << ": " << r.err;
    }
    EXPECT_TRUE(dir.entries().empty());
}

}  // namespace
