// provenanceReadOptions: the read options a package's provenance records (what
// baker/bake/bake_pipeline.cpp's sharedMetadata writes), and the errors for a provenance that lacks them.
#include "reference/provenance_read_options.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "../support/error_code.h"

namespace firelook::reference {
namespace {

// A metadata document shaped like a real package's (the "bake" description left out: unread here).
nlohmann::json bakedMetadata() {
    return nlohmann::json::parse(R"({
      "provenance": {
        "tool": "firelook", "tool_version": "test", "sequence": "samples/data/explosion",
        "sequence_frames": [1, 2, 3], "density_grid": "smoke", "temperature_grid": "flame",
        "temperature_scale": 1000.0, "temperature_offset": 300.0, "clamp_extreme": false,
        "sources": [], "settings": {"seed": 1}, "settings_xxh3_64": "0"
      },
      "camera": {"source": "default"}
    })");
}

TEST(ProvenanceReadOptions, ReadsWhatTheBakeRecorded) {
    const vdb::ReadOptions read = provenanceReadOptions(bakedMetadata().dump(), "fire.firelook");
    EXPECT_EQ(read.density_grid, "smoke");
    EXPECT_EQ(read.temperature_grid, "flame");
    EXPECT_EQ(read.temperature_scale, 1000.0);
    EXPECT_EQ(read.temperature_offset, 300.0);
    EXPECT_EQ(read.density_scale, 1.0);  // recorded only when not 1
    EXPECT_FALSE(read.clamp_extreme);
    EXPECT_FALSE(read.strict);  // policies are the caller's
}

TEST(ProvenanceReadOptions, ClampExtremeAndDensityScaleWhenRecorded) {
    nlohmann::json meta = bakedMetadata();
    meta["provenance"]["clamp_extreme"] = true;
    meta["provenance"]["density_scale"] = 2.5;
    const vdb::ReadOptions read = provenanceReadOptions(meta.dump(), "fire.firelook");
    EXPECT_TRUE(read.clamp_extreme);
    EXPECT_EQ(read.density_scale, 2.5);

    // Packages baked before clamp_extreme was recorded read unclamped.
    meta["provenance"].erase("clamp_extreme");
    EXPECT_FALSE(provenanceReadOptions(meta.dump(), "fire.firelook").clamp_extreme);
}

TEST(ProvenanceReadOptions, MissingDensityGridNamesThePackageAndTheEntry) {
    nlohmann::json meta = bakedMetadata();
    meta["provenance"].erase("density_grid");
    try {
        provenanceReadOptions(meta.dump(), "fire.firelook");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::NotFound);
        EXPECT_EQ(std::string(e.what()),
                  "fire.firelook: the provenance records no density_grid (needed to read the sequence as the bake did)");
    }
}

TEST(ProvenanceReadOptions, RefusesMetadataWithoutAUsableProvenance) {
    EXPECT_ERROR_CODE(ErrorCode::NotFound, provenanceReadOptions(R"({"camera": {}})", "p"));
    EXPECT_ERROR_CODE(ErrorCode::Corrupt, provenanceReadOptions("{not json", "p"));
    EXPECT_ERROR_CODE(ErrorCode::Corrupt, provenanceReadOptions(R"({"provenance": 3})", "p"));
    nlohmann::json meta = bakedMetadata();
    meta["provenance"]["temperature_scale"] = "1000";
    try {
        provenanceReadOptions(meta.dump(), "fire.firelook");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::Corrupt);
        EXPECT_EQ(std::string(e.what()), "fire.firelook: provenance.temperature_scale is not a number (\"1000\")");
    }
}

}  // namespace
}  // namespace firelook::reference
