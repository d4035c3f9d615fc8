// An image with its caption above, for the viewport's rows (ImGui over a GL texture).
#pragma once

#include <imgui.h>

#include "gl_util.h"

namespace firelook::viewer {

ImTextureID textureId(GLuint texture);
void imageWithCaption(const char* caption, GLuint texture, float width, float aspect);

}  // namespace firelook::viewer
