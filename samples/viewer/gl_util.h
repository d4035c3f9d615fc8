// Small OpenGL 3.3 core helpers: shader programs, owned textures and render targets, and pixel
// read-back. Entry points come straight from libGL (GL_GLEXT_PROTOTYPES, see CMakeLists.txt).
#pragma once

#include <GL/glcorearb.h>

#include <string>
#include <vector>

namespace firelook::viewer::gl {

// Compiles and links; throws ViewerError with the driver's log.
GLuint makeProgram(const std::string& vertex_source, const std::string& fragment_source, const char* name);

// The vertex shader of every full-screen pass: one triangle covering the viewport, no buffers.
const char* fullScreenVertexShader();

// A texture name that deletes itself.
class Texture {
  public:
    Texture() = default;
    ~Texture() { reset(); }
    Texture(Texture&& other) noexcept : id_(other.id_) { other.id_ = 0; }
    Texture& operator=(Texture&& other) noexcept;
    Texture(const Texture&) = delete;
    Texture& operator=(const Texture&) = delete;

    GLuint id() const { return id_; }
    explicit operator bool() const { return id_ != 0; }
    void reset();
    // A fresh name (deleting any previous one), bound to `target`, nearest filtering, clamped.
    void create(GLenum target);

  private:
    GLuint id_ = 0;
};

// A 2D colour texture with a framebuffer that renders into it.
class RenderTarget {
  public:
    RenderTarget() = default;
    ~RenderTarget() { reset(); }
    RenderTarget(const RenderTarget&) = delete;
    RenderTarget& operator=(const RenderTarget&) = delete;

    // (Re)allocates when the size or format changes. Throws ViewerError if the FBO is incomplete.
    void ensure(int width, int height, GLenum internal_format);
    void reset();
    void bind() const;  // framebuffer and viewport
    GLuint texture() const { return texture_.id(); }
    GLuint framebuffer() const { return fbo_; }
    int width() const { return width_; }
    int height() const { return height_; }

    // RGBA float rows in memory order (row 0 = the first row rendered, our images' top row).
    void readRgba(std::vector<float>& out) const;
    // RGBA 8-bit.
    void readRgba8(std::vector<unsigned char>& out) const;

  private:
    Texture texture_;
    GLuint fbo_ = 0;
    int width_ = 0, height_ = 0;
    GLenum format_ = 0;
};

// An empty vertex array object (core profile needs one bound to draw).
GLuint emptyVertexArray();

}  // namespace firelook::viewer::gl
