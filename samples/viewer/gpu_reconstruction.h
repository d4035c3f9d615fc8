// Reconstruction on the GPU from the package's factors (the paper's real-time step):
//   rgb(p) = max(0, sum_k U[p][k] z[k]),  alpha(p) = mean_s 1 - exp(-(a O_a(s, p) + b O_b(s, p)))
// exactly as documented on fl_instance_state. U is a GL_TEXTURE_2D_ARRAY of RGBA16F layers (4 rank
// components per layer, straight from fl_instance_get_frame_u), the optical depths a float texture
// array (fl_instance_get_frame_depths' R32F layers regrouped four footprint samples to an RGBA32F
// texel, so one fetch serves four samples), and z a std140 uniform block. Both come from the frame
// the world already holds for the instance (no second decode). Frames' textures are cached (least
// recently used first out, bounded in bytes) so playback uploads a frame only after eviction.
// The shader is the plugin's plugin_api/shaders/firelook_reconstruct.glsl (its inputs documented
// there), embedded at build time.
#pragma once

#include <cstdint>
#include <list>
#include <vector>

#include "firelook/firelook.h"
#include "gl_util.h"

namespace firelook::viewer {

class GpuReconstruction {
  public:
    // Compiles the shader for the package's largest rank. Throws ViewerError if this GL cannot
    // hold it (too many array layers or a too large uniform block): use the CPU path then.
    // `instance` of `world` is the one drawn: textures are taken from the frame its last update showed.
    GpuReconstruction(fl_world world, fl_instance instance, const fl_package_info& info,
                      size_t cache_bytes = size_t{512} << 20);
    ~GpuReconstruction();
    GpuReconstruction(const GpuReconstruction&) = delete;
    GpuReconstruction& operator=(const GpuReconstruction&) = delete;

    // Makes the textures of the frame the instance's last update showed (state.frame) resident;
    // returns true if it had to upload them.
    bool prepareFrame(const fl_instance_state& state);
    // z: rank x 3 floats of the last update.
    void uploadCoefficients(const std::vector<float>& z, int rank);
    // Draws the state's frame with its extinction and alpha layers into `target` (RGBA32F, package
    // size); `state` is the instance's last update's.
    void draw(const fl_instance_state& state, gl::RenderTarget& target);

  private:
    struct FrameTextures {
        int frame = 0;
        int layers = 0;
        gl::Texture u, depths;
        size_t bytes = 0;
    };
    FrameTextures& resident(int frame, bool& uploaded);

    fl_world world_;
    fl_instance instance_;
    fl_package_info info_;
    size_t cache_bytes_;
    int max_layers_ = 1;  // U layers of the largest rank (4 rank components each)
    int groups_ = 1;      // texels of four footprint samples
    GLuint program_ = 0;
    GLuint ubo_ = 0;
    GLint loc_layers_ = -1, loc_lower_ = -1, loc_upper_ = -1, loc_t_ = -1, loc_a_ = -1, loc_b_ = -1;
    std::list<FrameTextures> cache_;  // front = most recently used
    std::vector<float> z_packed_;
    std::vector<uint16_t> u_buffer_;
    std::vector<float> depth_buffer_, depth_packed_;
};

}  // namespace firelook::viewer
