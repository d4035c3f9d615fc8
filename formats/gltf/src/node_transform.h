// A glTF node's local transform.
#pragma once

#include <tiny_gltf.h>

#include <glm/mat4x4.hpp>
#include <string>

namespace firelook::gltf::detail {

// The node's matrix when it has one, else translation * rotation * scale (glTF 2.0, 5.25), with the
// rotation quaternion normalised. Throws GltfError prefixed with `where` for arrays of the wrong
// length, non-finite numbers or a zero quaternion.
glm::dmat4 localTransform(const tinygltf::Node& node, const std::string& where);

}  // namespace firelook::gltf::detail
