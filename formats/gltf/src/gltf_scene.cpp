#include "gltf/gltf_scene.h"

#include <cmath>
#include <cstddef>
#include <numbers>
#include <utility>

#include "model_loading.h"
#include "node_transform.h"

namespace firelook::gltf {
namespace {

// Walks the default scene's node tree depth first and collects what FireLook uses from it.
class SceneCollector {
  public:
    SceneCollector(const std::filesystem::path& path, const tinygltf::Model& model)
        : file_(path.string()), model_(model), reached_(model.nodes.size(), false) {}

    Scene collect() {
        // An explicit stack rather than recursion, so a very deep hierarchy cannot exhaust the call stack.
        std::vector<std::pair<int, glm::dmat4>> pending;
        const std::vector<int> roots = rootNodes();
        for (auto root = roots.rbegin(); root != roots.rend(); ++root)
            pending.emplace_back(*root, glm::dmat4(1.0));
        while (!pending.empty()) {
            const auto [index, parent_world] = pending.back();
            pending.pop_back();
            const tinygltf::Node& node = nodeAt(index);
            const glm::dmat4 world = parent_world * detail::localTransform(node, nodeName(index));
            visit(index, node, world);
            for (auto child = node.children.rbegin(); child != node.children.rend(); ++child) {
                pending.emplace_back(*child, world);
            }
        }
        return finish();
    }

  private:
    std::vector<int> rootNodes() const {
        if (!model_.scenes.empty()) {
            const int scene = model_.defaultScene < 0 ? 0 : model_.defaultScene;
            if (scene >= static_cast<int>(model_.scenes.size())) {
                throw GltfError(file_ + ": default scene " + std::to_string(scene) + " does not exist (" +
                                std::to_string(model_.scenes.size()) + " scenes)");
            }
            return model_.scenes[static_cast<std::size_t>(scene)].nodes;
        }
        // No scenes at all: every node that is no other node's child is a root.
        std::vector<bool> is_child(model_.nodes.size(), false);
        for (const tinygltf::Node& node : model_.nodes) {
            for (int child : node.children) {
                if (child >= 0 && child < static_cast<int>(model_.nodes.size())) {
                    is_child[static_cast<std::size_t>(child)] = true;
                }
            }
        }
        std::vector<int> roots;
        for (std::size_t i = 0; i < model_.nodes.size(); ++i) {
            if (!is_child[i]) roots.push_back(static_cast<int>(i));
        }
        return roots;
    }

    const tinygltf::Node& nodeAt(int index) {
        if (index < 0 || index >= static_cast<int>(model_.nodes.size())) {
            throw GltfError(file_ + ": node index " + std::to_string(index) + " is out of range (" +
                            std::to_string(model_.nodes.size()) + " nodes)");
        }
        // glTF requires the node hierarchy to be a set of disjoint trees; this also stops cycles.
        if (reached_[static_cast<std::size_t>(index)]) {
            throw GltfError(nodeName(index) + ": reached twice; the node hierarchy is not a tree");
        }
        reached_[static_cast<std::size_t>(index)] = true;
        return model_.nodes[static_cast<std::size_t>(index)];
    }

    std::string nodeName(int index) const {
        const std::string& name = model_.nodes[static_cast<std::size_t>(index)].name;
        return file_ + ": node " + std::to_string(index) + (name.empty() ? "" : " '" + name + "'");
    }

    void visit(int index, const tinygltf::Node& node, const glm::dmat4& world) {
        if (node.camera >= 0) visitCamera(index, node, world);
        const auto extension = node.extensions.find("KHR_lights_punctual");
        if (extension != node.extensions.end()) visitLight(index, node, extension->second, world);
    }

    void visitCamera(int index, const tinygltf::Node& node, const glm::dmat4& world) {
        if (node.camera >= static_cast<int>(model_.cameras.size())) {
            throw GltfError(nodeName(index) + ": camera index " + std::to_string(node.camera) +
                            " is out of range");
        }
        const tinygltf::Camera& camera = model_.cameras[static_cast<std::size_t>(node.camera)];
        const std::string name = camera.name.empty() ? node.name : camera.name;
        if (camera.type != "perspective") {
            if (first_other_camera_.empty()) first_other_camera_ = "'" + name + "' (" + camera.type + ")";
            return;
        }
        if (camera_) return;  // only the first perspective camera is used
        const tinygltf::PerspectiveCamera& lens = camera.perspective;
        const std::string where = file_ + ": camera '" + name + "'";
        if (!(lens.yfov > 0.0 && lens.yfov < std::numbers::pi)) {
            throw GltfError(where + ": yfov " + std::to_string(lens.yfov) + " is not in (0, pi)");
        }
        if (!(lens.znear > 0.0) || !std::isfinite(lens.znear)) {
            throw GltfError(where + ": znear " + std::to_string(lens.znear) + " is not positive");
        }
        PerspectiveCamera result;
        result.name = name;
        result.world_from_camera = world;
        result.yfov_radians = lens.yfov;
        if (lens.aspectRatio > 0.0) result.aspect_ratio = lens.aspectRatio;
        result.znear = lens.znear;
        if (lens.zfar > 0.0) result.zfar = lens.zfar;  // 0 is tinygltf's "absent": infinite
        camera_ = std::move(result);
    }

    void visitLight(int index, const tinygltf::Node& node, const tinygltf::Value& extension,
                    const glm::dmat4& world) {
        if (!extension.IsObject() || !extension.Has("light") || !extension.Get("light").IsNumber()) {
            throw GltfError(nodeName(index) + ": KHR_lights_punctual has no light index");
        }
        const int light_index = extension.Get("light").GetNumberAsInt();
        if (light_index < 0 || light_index >= static_cast<int>(model_.lights.size())) {
            throw GltfError(nodeName(index) + ": light index " + std::to_string(light_index) +
                            " is out of range (" + std::to_string(model_.lights.size()) + " lights)");
        }
        const tinygltf::Light& light = model_.lights[static_cast<std::size_t>(light_index)];
        if (light.type != "directional") {
            ++ignored_lights_;
            return;
        }
        const std::string name = light.name.empty() ? node.name : light.name;
        const std::string where = file_ + ": light '" + name + "'";
        // The light shines along the node's -Z axis, which world maps to minus its third column.
        const glm::dvec3 direction = -glm::dvec3(world[2]);
        const double length = glm::length(direction);
        if (!(length > 1e-12) || !std::isfinite(length)) {
            throw GltfError(where + ": its node's transform collapses the -Z axis, so it has no direction");
        }
        DirectionalLight result;
        result.name = name;
        result.direction = direction / length;
        if (!light.color.empty()) {
            if (light.color.size() != 3) throw GltfError(where + ": 'color' must have 3 numbers");
            result.color = glm::dvec3(light.color[0], light.color[1], light.color[2]);
        }
        result.intensity = light.intensity;
        lights_.push_back(std::move(result));
    }

    Scene finish() {
        if (!camera_ && !first_other_camera_.empty()) {
            throw GltfError(file_ + ": camera " + first_other_camera_ +
                            " is not perspective, and FireLook renders only perspective cameras");
        }
        if (!camera_ && lights_.empty()) {
            throw GltfError(file_ +
                            ": the default scene has none of what FireLook reads: no perspective camera "
                            "and no directional light (KHR_lights_punctual) on its nodes");
        }
        return Scene{std::move(camera_), std::move(lights_), ignored_lights_};
    }

    std::string file_;
    const tinygltf::Model& model_;
    std::vector<bool> reached_;
    std::optional<PerspectiveCamera> camera_;
    std::string first_other_camera_;
    std::vector<DirectionalLight> lights_;
    int ignored_lights_ = 0;
};

}  // namespace

Scene loadScene(const std::filesystem::path& path) {
    const tinygltf::Model model = detail::loadModel(path);
    return SceneCollector(path, model).collect();
}

}  // namespace firelook::gltf
