#include "ui_image.h"

#include <cstdint>

namespace firelook::viewer {

ImTextureID textureId(GLuint texture) { return reinterpret_cast<ImTextureID>(static_cast<intptr_t>(texture)); }

void imageWithCaption(const char* caption, GLuint texture, float width, float aspect) {
    ImGui::BeginGroup();
    ImGui::TextUnformatted(caption);
    if (texture) ImGui::Image(textureId(texture), ImVec2(width, width * aspect));
    ImGui::EndGroup();
}

}  // namespace firelook::viewer
