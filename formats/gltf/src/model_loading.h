// Reading a glTF file into tinygltf's model, with errors that name the file.
#pragma once

#include <tiny_gltf.h>

#include <filesystem>

namespace firelook::gltf::detail {

// .glb is recognised by its magic bytes, whatever the extension; anything else is parsed as JSON.
// Images are not decoded (only cameras and lights are needed). Throws GltfError naming the file.
tinygltf::Model loadModel(const std::filesystem::path& path);

}  // namespace firelook::gltf::detail
