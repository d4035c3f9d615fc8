#include "node_transform.h"

#include <cmath>
#include <glm/ext/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <vector>

#include "gltf/gltf_scene.h"

namespace firelook::gltf::detail {
namespace {

void checkArray(const std::vector<double>& values, std::size_t expected_size, const char* property,
                const std::string& where) {
    if (!values.empty() && values.size() != expected_size) {
        throw GltfError(where + ": '" + property + "' has " + std::to_string(values.size()) +
                        " numbers, not " + std::to_string(expected_size));
    }
    for (double value : values) {
        if (!std::isfinite(value)) throw GltfError(where + ": '" + property + "' holds a non-finite number");
    }
}

}  // namespace

glm::dmat4 localTransform(const tinygltf::Node& node, const std::string& where) {
    checkArray(node.matrix, 16, "matrix", where);
    checkArray(node.translation, 3, "translation", where);
    checkArray(node.rotation, 4, "rotation", where);
    checkArray(node.scale, 3, "scale", where);
    if (!node.matrix.empty()) return glm::make_mat4(node.matrix.data());  // both column-major

    glm::dmat4 transform(1.0);
    if (!node.translation.empty())
        transform = glm::translate(transform, glm::make_vec3(node.translation.data()));
    if (!node.rotation.empty()) {
        // glTF stores (x, y, z, w); GLM's constructor takes w first.
        const glm::dquat rotation(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
        const double length = glm::length(rotation);
        if (length == 0.0) throw GltfError(where + ": 'rotation' is the zero quaternion");
        transform *= glm::mat4_cast(rotation / length);
    }
    if (!node.scale.empty()) transform = glm::scale(transform, glm::make_vec3(node.scale.data()));
    return transform;
}

}  // namespace firelook::gltf::detail
