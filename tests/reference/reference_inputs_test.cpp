// referenceInputs: the medium, camera and look model of one frame of a package, with the sequence
// read as the package's provenance says (the viewer's QA reference, samples/viewer/reference_worker.cpp).
#include "reference/reference_inputs.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "../support/error_code.h"
#include "../support/sample.h"
#include "../vdb/vdb_test_files.h"
#include "look/look.h"
#include "reference/frame_medium.h"
#include "vdb/vdb_sequence.h"

namespace firelook::reference {
namespace {

using firelook::testing::kSample;

// Provenance as `firelook bake samples/data/explosion` records it (baker/bake/bake_pipeline.cpp).
nlohmann::json sampleProvenance() {
    return {{"tool", "firelook"},         {"sequence", kSample},
            {"density_grid", "density"},  {"temperature_grid", "temperature"},
            {"temperature_scale", 1.0},   {"temperature_offset", 0.0},
            {"clamp_extreme", false},     {"sources", nlohmann::json::array()}};
}

BakedScene sceneWith(const nlohmann::json& provenance) {
    BakedScene scene;
    scene.metadata_json = nlohmann::json{{"provenance", provenance}}.dump();
    scene.camera.width = 48;
    scene.camera.height = 32;
    scene.light_directions = {{0.0, 0.0, -1.0}};  // defaultLook() has one light
    scene.bins = {0.0, 3.0, 16};
    scene.rbf_width = 1.0;
    return scene;
}

const std::string kLook = lookToJson(defaultLook());

TEST(ReferenceInputs, Frame7OfTheSampleIsTheMediumTheBakeTraces) {
    // What the bake traces: the sequence opened with the options it records, made a medium by the
    // same dense copy (bake_pipeline.cpp).
    const render::Medium baked = mediumFromFrame(vdb::VdbSequence::open(kSample).load(7));
    const ReferenceInputs in = referenceInputs(sceneWith(sampleProvenance()), "fire.firelook", kSample, 7, kLook);

    ASSERT_FALSE(baked.empty());
    EXPECT_GT(static_cast<long>(baked.dims().x) * baked.dims().y * baked.dims().z, 1000);
    EXPECT_EQ(in.medium.dims(), baked.dims());
    EXPECT_EQ(in.medium.origin(), baked.origin());
    EXPECT_EQ(in.medium.worldBounds().min, baked.worldBounds().min);
    EXPECT_EQ(in.medium.worldBounds().max, baked.worldBounds().max);
    const glm::ivec3 centre = baked.dims() / 2;
    EXPECT_EQ(in.medium.voxel(centre).density, baked.voxel(centre).density);
    EXPECT_EQ(in.medium.voxel(centre).temperature, baked.voxel(centre).temperature);

    EXPECT_EQ(in.camera.width(), 48);
    EXPECT_EQ(in.camera.height(), 32);
    ASSERT_EQ(in.model.lights.size(), 1u);
    EXPECT_EQ(in.model.bins.count, 16);
    EXPECT_EQ(in.model.bins.t_hi, 3.0);
}

TEST(ReferenceInputs, TheProvenancesMappingIsApplied) {
    const render::Medium raw = mediumFromFrame(vdb::VdbSequence::open(kSample).load(7));
    nlohmann::json provenance = sampleProvenance();
    provenance["density_scale"] = 2.0;
    provenance["temperature_scale"] = 2.0;
    provenance["temperature_offset"] = 100.0;
    const ReferenceInputs in = referenceInputs(sceneWith(provenance), "fire.firelook", kSample, 7, kLook);
    ASSERT_EQ(in.medium.dims(), raw.dims());
    double density_sum = 0.0;
    for (int k = 0; k < raw.dims().z; ++k)
        for (int j = 0; j < raw.dims().y; ++j)
            for (int i = 0; i < raw.dims().x; ++i) {
                const render::MediumSample a = raw.voxel({i, j, k}), b = in.medium.voxel({i, j, k});
                ASSERT_EQ(b.density, 2.0f * a.density) << i << " " << j << " " << k;
                ASSERT_NEAR(b.temperature, 2.0f * a.temperature + 100.0f, 1e-4f) << i << " " << j << " " << k;
                density_sum += a.density;
            }
    EXPECT_GT(density_sum, 0.0);
}

// The viewer's reference once ignored the recorded --clamp-extreme: a frame with a density beyond
// the plausible range is refused without it and clamped with it.
TEST(ReferenceInputs, ClampExtremeRecordedInTheProvenanceIsHonoured) {
    using namespace vdb::testing;
    TempDir dir;
    writeVdb(dir / "f_1.vdb", {makeGrid("density", {{{0, 0, 0}, 0.5f}, {{1, 0, 0}, 1e30f}}),
                               makeGrid("temperature", kTemperature)});
    nlohmann::json provenance = sampleProvenance();
    const std::string sequence = dir.path().string();

    EXPECT_ERROR_CODE(ErrorCode::BadVolume, referenceInputs(sceneWith(provenance), "p", sequence, 1, kLook));

    provenance["clamp_extreme"] = true;
    const ReferenceInputs in = referenceInputs(sceneWith(provenance), "p", sequence, 1, kLook);
    EXPECT_EQ(in.medium.voxel(glm::ivec3(1, 0, 0) - in.medium.origin()).density, 1e6f);
    EXPECT_EQ(in.medium.voxel(glm::ivec3(0, 0, 0) - in.medium.origin()).density, 0.5f);
}

TEST(ReferenceInputs, ErrorsNameTheirSource) {
    nlohmann::json provenance = sampleProvenance();
    provenance.erase("temperature_grid");
    EXPECT_ERROR_CODE(ErrorCode::NotFound, referenceInputs(sceneWith(provenance), "p", kSample, 7, kLook));
    EXPECT_ERROR_CODE(ErrorCode::Look, referenceInputs(sceneWith(sampleProvenance()), "p", kSample, 7, "{}"));
    BakedScene bad_camera = sceneWith(sampleProvenance());
    bad_camera.camera.width = 0;
    EXPECT_ERROR_CODE(ErrorCode::InvalidArgument, referenceInputs(bad_camera, "p", kSample, 7, kLook));
}

}  // namespace
}  // namespace firelook::reference
