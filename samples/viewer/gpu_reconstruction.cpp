#include "gpu_reconstruction.h"

#include <algorithm>
#include <string>

#include "fl_check.h"
#include "reconstruct_shader.h"

namespace firelook::viewer {

GpuReconstruction::GpuReconstruction(fl_world world, fl_instance instance, const fl_package_info& info,
                                     size_t cache_bytes)
    : world_(world), instance_(instance), info_(info), cache_bytes_(cache_bytes) {
    max_layers_ = std::max(1, (info.max_rank + 3) / 4);
    groups_ = (info.footprint_samples + 3) / 4;
    const int depth_layers = groups_ * (1 + info.alpha_threshold_count);
    GLint max_array_layers = 0, max_block = 0;
    glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &max_array_layers);
    glGetIntegerv(GL_MAX_UNIFORM_BLOCK_SIZE, &max_block);
    if (depth_layers > max_array_layers || max_layers_ > max_array_layers)
        throw ViewerError("GPU path: the package needs " + std::to_string(std::max(depth_layers, max_layers_)) +
                          " texture array layers, this GL allows " + std::to_string(max_array_layers));
    const int block_bytes = 3 * max_layers_ * 16;
    if (block_bytes > max_block)
        throw ViewerError("GPU path: rank " + std::to_string(info.max_rank) + " needs a " +
                          std::to_string(block_bytes) + "-byte uniform block, this GL allows " +
                          std::to_string(max_block));

    // The two lines the shader file asks its host for (plugin_api/shaders/firelook_reconstruct.glsl).
    const std::string fragment =
        "#version 330 core\n#define MAX_LAYERS " + std::to_string(max_layers_) + "\n" + kReconstructShader;
    program_ = gl::makeProgram(gl::fullScreenVertexShader(), fragment, "reconstruction");
    glUseProgram(program_);
    glUniform1i(glGetUniformLocation(program_, "u_factors"), 0);
    glUniform1i(glGetUniformLocation(program_, "u_depths"), 1);
    glUniformBlockBinding(program_, glGetUniformBlockIndex(program_, "Coefficients"), 0);
    // Footprint samples are fixed per package: set once.
    glUniform1i(glGetUniformLocation(program_, "u_groups"), groups_);
    glUniform1i(glGetUniformLocation(program_, "u_samples"), info.footprint_samples);
    const int in_last = info.footprint_samples - 4 * (groups_ - 1);
    glUniform4f(glGetUniformLocation(program_, "u_last_mask"), 1.0f, in_last > 1 ? 1.0f : 0.0f,
                in_last > 2 ? 1.0f : 0.0f, in_last > 3 ? 1.0f : 0.0f);
    loc_layers_ = glGetUniformLocation(program_, "u_layers");
    loc_lower_ = glGetUniformLocation(program_, "u_lower");
    loc_upper_ = glGetUniformLocation(program_, "u_upper");
    loc_t_ = glGetUniformLocation(program_, "u_t");
    loc_a_ = glGetUniformLocation(program_, "u_extinction_a");
    loc_b_ = glGetUniformLocation(program_, "u_extinction_b");
    glUseProgram(0);

    glGenBuffers(1, &ubo_);
    glBindBuffer(GL_UNIFORM_BUFFER, ubo_);
    glBufferData(GL_UNIFORM_BUFFER, block_bytes, nullptr, GL_DYNAMIC_DRAW);
    glBindBuffer(GL_UNIFORM_BUFFER, 0);
    z_packed_.assign(static_cast<size_t>(3 * max_layers_) * 4, 0.0f);
}

GpuReconstruction::~GpuReconstruction() {
    cache_.clear();
    if (ubo_) glDeleteBuffers(1, &ubo_);
    if (program_) glDeleteProgram(program_);
}

GpuReconstruction::FrameTextures& GpuReconstruction::resident(int frame, bool& uploaded) {
    uploaded = false;
    for (auto it = cache_.begin(); it != cache_.end(); ++it)
        if (it->frame == frame) {
            cache_.splice(cache_.begin(), cache_, it);
            return cache_.front();
        }
    const size_t w = static_cast<size_t>(info_.width), h = static_cast<size_t>(info_.height), pixels = w * h;
    FrameTextures t;
    t.frame = frame;

    // U as the API hands it out: already RGBA16F layers, from the frame the world holds for the
    // instance (the frame its last update showed, which is `frame`: see prepareFrame).
    size_t count = 0;
    check(fl_instance_get_frame_u(world_, instance_, nullptr, 0, &count), "fl_instance_get_frame_u");
    u_buffer_.resize(count);
    check(fl_instance_get_frame_u(world_, instance_, u_buffer_.data(), u_buffer_.size(), &count),
          "fl_instance_get_frame_u");
    t.layers = static_cast<int>(count / (pixels * 4));
    t.u.create(GL_TEXTURE_2D_ARRAY);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_RGBA16F, info_.width, info_.height, t.layers, 0, GL_RGBA, GL_HALF_FLOAT,
                 u_buffer_.data());

    // Optical depths: S single-channel O_b layers then S x T O_a layers (sample-major), regrouped
    // four samples to a texel (see the shader). Values are copied, never changed.
    check(fl_instance_get_frame_depths(world_, instance_, nullptr, 0, &count), "fl_instance_get_frame_depths");
    depth_buffer_.resize(count);
    check(fl_instance_get_frame_depths(world_, instance_, depth_buffer_.data(), depth_buffer_.size(), &count),
          "fl_instance_get_frame_depths");
    const int samples = info_.footprint_samples, thresholds = info_.alpha_threshold_count;
    const int layers = groups_ * (1 + thresholds);
    depth_packed_.assign(static_cast<size_t>(layers) * pixels * 4, 0.0f);
    const auto pack = [&](int source_layer, int target_layer, int channel) {
        const float* from = depth_buffer_.data() + static_cast<size_t>(source_layer) * pixels;
        float* to = depth_packed_.data() + static_cast<size_t>(target_layer) * pixels * 4 + channel;
        for (size_t p = 0; p < pixels; ++p) to[p * 4] = from[p];
    };
    for (int s = 0; s < samples; ++s) {
        pack(s, s / 4, s % 4);
        for (int j = 0; j < thresholds; ++j) pack(samples + s * thresholds + j, groups_ + j * groups_ + s / 4, s % 4);
    }
    t.depths.create(GL_TEXTURE_2D_ARRAY);
    glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_RGBA32F, info_.width, info_.height, layers, 0, GL_RGBA, GL_FLOAT,
                 depth_packed_.data());
    glBindTexture(GL_TEXTURE_2D_ARRAY, 0);
    t.bytes = u_buffer_.size() * sizeof(uint16_t) + depth_packed_.size() * sizeof(float);

    // Evict least recently used frames beyond the budget (the new one always stays).
    size_t total = t.bytes;
    for (const FrameTextures& c : cache_) total += c.bytes;
    while (!cache_.empty() && total > cache_bytes_) {
        total -= cache_.back().bytes;
        cache_.pop_back();
    }
    cache_.push_front(std::move(t));
    uploaded = true;
    return cache_.front();
}

bool GpuReconstruction::prepareFrame(const fl_instance_state& state) {
    bool uploaded = false;
    resident(state.frame, uploaded);
    return uploaded;
}

void GpuReconstruction::uploadCoefficients(const std::vector<float>& z, int rank) {
    // z[3 l + ch] holds channel ch of rank components 4 l .. 4 l + 3; zero beyond the rank so the
    // last layer's padding adds exact zeros.
    std::fill(z_packed_.begin(), z_packed_.end(), 0.0f);
    const int n = std::min(rank, 4 * max_layers_);
    for (int k = 0; k < n; ++k)
        for (int c = 0; c < 3; ++c)
            z_packed_[static_cast<size_t>(3 * (k / 4) + c) * 4 + static_cast<size_t>(k % 4)] =
                z[static_cast<size_t>(k) * 3 + c];
    glBindBuffer(GL_UNIFORM_BUFFER, ubo_);
    glBufferSubData(GL_UNIFORM_BUFFER, 0, static_cast<GLsizeiptr>(z_packed_.size() * sizeof(float)), z_packed_.data());
    glBindBuffer(GL_UNIFORM_BUFFER, 0);
}

void GpuReconstruction::draw(const fl_instance_state& state, gl::RenderTarget& target) {
    bool uploaded = false;
    const FrameTextures& t = resident(state.frame, uploaded);
    target.ensure(info_.width, info_.height, GL_RGBA32F);
    target.bind();
    glDisable(GL_BLEND);
    glDisable(GL_SCISSOR_TEST);
    glUseProgram(program_);
    glUniform1i(loc_layers_, t.layers);
    glUniform1i(loc_lower_, state.alpha_layer_lower);
    glUniform1i(loc_upper_, state.alpha_layer_upper);
    glUniform1f(loc_t_, state.alpha_layer_t);
    glUniform1f(loc_a_, state.extinction_a);
    glUniform1f(loc_b_, state.extinction_b);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D_ARRAY, t.u.id());
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D_ARRAY, t.depths.id());
    glBindBufferBase(GL_UNIFORM_BUFFER, 0, ubo_);
    glBindVertexArray(gl::emptyVertexArray());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glBindTexture(GL_TEXTURE_2D_ARRAY, 0);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D_ARRAY, 0);
    glUseProgram(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace firelook::viewer
