// The display pass: linear premultiplied RGBA (+ lens flare) composited over a background,
//   final = 2^exposure (rgb + flare) + (1 - alpha) * background,
// clamped and sRGB-encoded into an RGBA8 texture that ImGui shows. Also the GPU-vs-CPU difference
// view |a - b| * gain. The exposure scales the fire's light only; the background is a display
// colour. Files written by export and the screenshots are taken before this pass (linear values).
#pragma once

#include "gl_util.h"
#include "look_edit.h"

namespace firelook::viewer {

struct DisplaySettings {
    float exposure_stops = 0.0f;
    bool checker = true;                    // else the solid colour
    Rgb3 solid{0.02f, 0.02f, 0.025f};       // linear
    Rgb3 checker_dark{0.015f, 0.015f, 0.015f}, checker_light{0.05f, 0.05f, 0.05f};
    int checker_pixels = 16;
};

class Compositor {
  public:
    Compositor();
    ~Compositor();
    Compositor(const Compositor&) = delete;
    Compositor& operator=(const Compositor&) = delete;

    // `flare` 0: none. `target` becomes RGBA8 of the source's size.
    void composite(const gl::RenderTarget& source, GLuint flare, const DisplaySettings& settings,
                   gl::RenderTarget& target);
    // |a - b| per RGB channel times `gain`, over black.
    void difference(const gl::RenderTarget& a, const gl::RenderTarget& b, float gain, gl::RenderTarget& target);

  private:
    void draw(const gl::RenderTarget& source, GLuint other, GLuint flare, int mode, float scale,
              const DisplaySettings& settings, gl::RenderTarget& target);

    GLuint program_ = 0;
};

// RGBA8 data (top row first) into a texture target of that size.
void uploadRgba8(const std::vector<unsigned char>& rgba, int width, int height, gl::RenderTarget& target);

}  // namespace firelook::viewer
