#include "cpu_path.h"

namespace firelook::viewer {

void uploadRgba(const std::vector<float>& rgba, int width, int height, gl::RenderTarget& target) {
    target.ensure(width, height, GL_RGBA32F);
    glBindTexture(GL_TEXTURE_2D, target.texture());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    // Row 0 of the data becomes texture row 0, as the GPU path writes row 0 = top row.
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, GL_RGBA, GL_FLOAT, rgba.data());
    glBindTexture(GL_TEXTURE_2D, 0);
}

}  // namespace firelook::viewer
