// The CPU path (fallback and comparison): the library's own reconstruction (fl_instance_get_image)
// uploaded into the same kind of RGBA32F target the GPU path renders into, so everything after it
// (display, read-back, screenshots) is shared by both paths.
#pragma once

#include <vector>

#include "fire_session.h"
#include "gl_util.h"

namespace firelook::viewer {

// Uploads width x height x 4 floats (top row first) into `target` (made RGBA32F of that size).
void uploadRgba(const std::vector<float>& rgba, int width, int height, gl::RenderTarget& target);

class CpuPath {
  public:
    // Reads the session's CPU image of the last update (the image output must be on).
    void fetch(const FireSession& session) { session.readImage(image_); }
    void upload(const FireSession& session, gl::RenderTarget& target) const {
        uploadRgba(image_, session.info().width, session.info().height, target);
    }
    const std::vector<float>& image() const { return image_; }

  private:
    std::vector<float> image_;
};

}  // namespace firelook::viewer
