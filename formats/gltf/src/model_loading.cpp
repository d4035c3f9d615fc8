#include "model_loading.h"

#include <array>
#include <exception>
#include <fstream>
#include <string>

#include "gltf/gltf_scene.h"

namespace firelook::gltf::detail {
namespace {

// Leaves images undecoded: FireLook reads only cameras and lights, and a scene's textures should
// neither cost time nor make loading fail.
bool skipImage(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
               void*) {
    return true;
}

bool startsWithGlbMagic(const std::filesystem::path& path) {
    std::array<char, 4> magic{};
    std::ifstream in(path, std::ios::binary);
    in.read(magic.data(), magic.size());
    return in.gcount() == 4 && std::string(magic.data(), 4) == "glTF";
}

std::string trimmed(std::string text) {
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r' || text.back() == ' '))
        text.pop_back();
    return text;
}

}  // namespace

tinygltf::Model loadModel(const std::filesystem::path& path) {
    std::error_code status_error;
    if (!std::filesystem::is_regular_file(path, status_error)) {
        throw GltfError(ErrorCode::IoError, path.string() + ": no such glTF file");
    }
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(&skipImage, nullptr);
    tinygltf::Model model;
    std::string error;
    std::string warning;  // tinygltf's warnings concern data FireLook does not use
    bool loaded = false;
    try {
        loaded = startsWithGlbMagic(path) ? loader.LoadBinaryFromFile(&model, &error, &warning, path.string())
                                          : loader.LoadASCIIFromFile(&model, &error, &warning, path.string());
    } catch (const std::exception& exception) {
        error = exception.what();
    }
    if (!loaded) {
        throw GltfError(path.string() +
                        ": cannot parse glTF: " + (error.empty() ? "unknown error" : trimmed(error)));
    }
    return model;
}

}  // namespace firelook::gltf::detail
