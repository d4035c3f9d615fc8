#include "gltf/gltf_scene.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace firelook::gltf {
namespace {

const std::filesystem::path kDataDir = std::filesystem::path(FIRELOOK_TEST_DATA_DIR) / "gltf";

// The files hold rotations as quaternions with components cos 45 deg = 0.7071067811865476, exact to
// a double's last bit; the products along the hierarchy then differ from the literal matrices below
// by a few units in the last place, far inside this bound.
constexpr double kTolerance = 1e-12;

// Columns as glTF and GLM store them: expected[c] is column c.
void expectMatrixNear(const glm::dmat4& actual, const double (&expected)[4][4]) {
    for (int column = 0; column < 4; ++column) {
        for (int row = 0; row < 4; ++row) {
            EXPECT_NEAR(actual[column][row], expected[column][row], kTolerance)
                << "column " << column << " row " << row;
        }
    }
}

void expectVectorNear(const glm::dvec3& actual, const glm::dvec3& expected) {
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(actual[i], expected[i], kTolerance) << "component " << i;
}

// The message of the GltfError that loading `path` throws, or a test failure if it throws none or
// one of another code.
std::string loadError(const std::filesystem::path& path, ErrorCode code = ErrorCode::BadScene) {
    try {
        loadScene(path);
    } catch (const GltfError& error) {
        EXPECT_EQ(error.code(), code) << error.what();
        return error.what();
    }
    ADD_FAILURE() << "loading " << path << " did not throw GltfError";
    return {};
}

TEST(GltfScene, CameraUnderTranslatedRotatedScaledParent) {
    const Scene scene = loadScene(kDataDir / "camera_trs.gltf");
    ASSERT_TRUE(scene.camera.has_value());
    const PerspectiveCamera& camera = *scene.camera;
    EXPECT_EQ(camera.name, "Main");
    // By hand: Rig = T(1,2,3) * Ry(90 deg) * S(1,1,2); Ry(90) sends +X to -Z and +Z to +X.
    // Rig's columns are R*S: (0,0,-1), (0,1,0), (2,0,0), origin (1,2,3).
    // CameraNode = Rig * T(0,0,5): origin = R*S*(0,0,5) + (1,2,3) = (10,0,0) + (1,2,3) = (11,2,3).
    const double expected[4][4] = {{0, 0, -1, 0}, {0, 1, 0, 0}, {2, 0, 0, 0}, {11, 2, 3, 1}};
    expectMatrixNear(camera.world_from_camera, expected);
    EXPECT_DOUBLE_EQ(camera.yfov_radians, 0.8);
    ASSERT_TRUE(camera.aspect_ratio.has_value());
    EXPECT_DOUBLE_EQ(*camera.aspect_ratio, 1.5);
    EXPECT_DOUBLE_EQ(camera.znear, 0.1);
    ASSERT_TRUE(camera.zfar.has_value());
    EXPECT_DOUBLE_EQ(*camera.zfar, 100.0);
}

TEST(GltfScene, DirectionalLightsTravelAlongTheirNodesMinusZ) {
    const Scene scene = loadScene(kDataDir / "camera_trs.gltf");
    ASSERT_EQ(scene.lights.size(), 2u);
    EXPECT_EQ(scene.ignored_lights, 1);  // the point light "Bulb"

    const DirectionalLight& key = scene.lights[0];  // walk order: Rig's child before the root SunNode
    EXPECT_EQ(key.name, "Key");
    // By hand: -Z through Rig's R*S is -(2,0,0), normalised (-1,0,0).
    expectVectorNear(key.direction, {-1, 0, 0});
    expectVectorNear(key.color, {1, 1, 1});  // glTF default colour
    EXPECT_DOUBLE_EQ(key.intensity, 1.0);    // glTF default intensity

    const DirectionalLight& sun = scene.lights[1];
    EXPECT_EQ(sun.name, "Sun");
    // By hand: Rx(-90 deg) has rows (1,0,0), (0,0,1), (0,-1,0); it sends (0,0,-1) to (0,-1,0): straight down.
    expectVectorNear(sun.direction, {0, -1, 0});
    expectVectorNear(sun.color, {1.0, 0.9, 0.8});
    EXPECT_DOUBLE_EQ(sun.intensity, 3.5);
}

TEST(GltfScene, CameraWithMatrixUnderTranslatedParent) {
    const Scene scene = loadScene(kDataDir / "camera_matrix.gltf");
    ASSERT_TRUE(scene.camera.has_value());
    const PerspectiveCamera& camera = *scene.camera;
    // "Unplaced" (camera 0) has no node; "Ortho" comes first on the walk but is not perspective;
    // "Second" comes after. The chosen camera has no name, so it takes its node's.
    EXPECT_EQ(camera.name, "MatrixCam");
    // By hand: T(5,0,0) * M, where M turns 180 deg about Y (X -> -X, Z -> -Z) and moves to (0,1,-10).
    const double expected[4][4] = {{-1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, -1, 0}, {5, 1, -10, 1}};
    expectMatrixNear(camera.world_from_camera, expected);
    EXPECT_DOUBLE_EQ(camera.yfov_radians, 0.5);
    EXPECT_DOUBLE_EQ(camera.znear, 0.05);
    EXPECT_FALSE(camera.aspect_ratio.has_value());
    EXPECT_FALSE(camera.zfar.has_value());
    EXPECT_TRUE(scene.lights.empty());
    EXPECT_EQ(scene.ignored_lights, 0);
}

TEST(GltfScene, OnlyTheDefaultSceneIsRead) {
    const Scene scene = loadScene(kDataDir / "default_scene.gltf");
    ASSERT_TRUE(scene.camera.has_value());
    EXPECT_EQ(scene.camera->name, "InSceneOne");
    EXPECT_DOUBLE_EQ(scene.camera->world_from_camera[3][2], 7.0);
}

TEST(GltfScene, LightsWithoutCameraOrScenes) {
    // No "scenes": parentless nodes are the roots. Unnamed light takes its node's name.
    const Scene scene = loadScene(kDataDir / "lights_only.gltf");
    EXPECT_FALSE(scene.camera.has_value());
    ASSERT_EQ(scene.lights.size(), 1u);
    EXPECT_EQ(scene.lights[0].name, "Moon");
    expectVectorNear(scene.lights[0].direction, {0, 0, -1});  // identity node: its own -Z
}

TEST(GltfScene, BinaryGlbGivesTheSameScene) {
    const auto temp =
        std::filesystem::temp_directory_path() / ("firelook-gltf-glb-" + std::to_string(::getpid()));
    std::filesystem::create_directories(temp);
    std::ifstream json_file(kDataDir / "camera_trs.gltf", std::ios::binary);
    std::stringstream json_text;
    json_text << json_file.rdbuf();
    std::string json = json_text.str();
    while (json.size() % 4 != 0) json += ' ';  // GLB chunks are 4-byte aligned, JSON padded with spaces

    // GLB 2.0: header (magic, version, total length), then one JSON chunk (length, type, data).
    const auto put32 = [](std::ofstream& out, std::uint32_t value) {
        const char bytes[4] = {static_cast<char>(value), static_cast<char>(value >> 8),
                               static_cast<char>(value >> 16), static_cast<char>(value >> 24)};
        out.write(bytes, 4);
    };
    const auto glb_path = temp / "camera_trs.glb";
    {
        std::ofstream out(glb_path, std::ios::binary);
        out.write("glTF", 4);
        put32(out, 2);
        put32(out, static_cast<std::uint32_t>(12 + 8 + json.size()));
        put32(out, static_cast<std::uint32_t>(json.size()));
        out.write("JSON", 4);
        out.write(json.data(), static_cast<std::streamsize>(json.size()));
    }
    const Scene binary = loadScene(glb_path);
    const Scene text = loadScene(kDataDir / "camera_trs.gltf");
    std::filesystem::remove_all(temp);

    ASSERT_TRUE(binary.camera.has_value());
    EXPECT_EQ(binary.camera->name, text.camera->name);
    EXPECT_EQ(binary.camera->world_from_camera,
              text.camera->world_from_camera);  // same numbers, same arithmetic
    ASSERT_EQ(binary.lights.size(), text.lights.size());
    EXPECT_EQ(binary.lights[1].direction, text.lights[1].direction);
    EXPECT_EQ(binary.ignored_lights, text.ignored_lights);
}

TEST(GltfScene, SceneWithNothingUsableIsAnError) {
    // Its one perspective camera is referenced by no node, so it has no placement and does not count.
    const std::string message = loadError(kDataDir / "nothing_usable.gltf");
    EXPECT_NE(message.find("nothing_usable.gltf"), std::string::npos) << message;
    EXPECT_NE(message.find("has none"), std::string::npos) << message;
}

TEST(GltfScene, OrthographicOnlyCameraIsReportedByName) {
    const std::string message = loadError(kDataDir / "orthographic_only.gltf");
    EXPECT_NE(message.find("orthographic_only.gltf"), std::string::npos) << message;
    EXPECT_NE(message.find("'TopView'"), std::string::npos) << message;
    EXPECT_NE(message.find("orthographic"), std::string::npos) << message;
}

TEST(GltfScene, MalformedFileIsAnErrorWithTheParserMessage) {
    const std::string message = loadError(kDataDir / "malformed.gltf");
    EXPECT_NE(message.find("malformed.gltf"), std::string::npos) << message;
    EXPECT_NE(message.find("cannot parse"), std::string::npos) << message;
    // Something from tinygltf follows our own words.
    EXPECT_GT(message.size(), message.find("cannot parse glTF: ") + std::string("cannot parse glTF: ").size())
        << message;
}

TEST(GltfScene, CyclicHierarchyIsAnErrorNotAHang) {
    const std::string message = loadError(kDataDir / "cycle.gltf");
    EXPECT_NE(message.find("cycle.gltf"), std::string::npos) << message;
    EXPECT_NE(message.find("not a tree"), std::string::npos) << message;
}

TEST(GltfScene, MissingFileIsAnError) {
    const std::string message = loadError(kDataDir / "does_not_exist.gltf", ErrorCode::IoError);
    EXPECT_NE(message.find("does_not_exist.gltf"), std::string::npos) << message;
}

}  // namespace
}  // namespace firelook::gltf
