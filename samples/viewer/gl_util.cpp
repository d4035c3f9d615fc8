#include "gl_util.h"

#include "fl_check.h"

namespace firelook::viewer::gl {
namespace {

GLuint compile(GLenum stage, const std::string& source, const char* name) {
    const GLuint shader = glCreateShader(stage);
    const char* text = source.c_str();
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        GLint length = 0;
        glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
        std::string log(static_cast<size_t>(length > 0 ? length : 1), '\0');
        glGetShaderInfoLog(shader, length, nullptr, log.data());
        glDeleteShader(shader);
        throw ViewerError(std::string("shader ") + name + " does not compile: " + log);
    }
    return shader;
}

}  // namespace

GLuint makeProgram(const std::string& vertex_source, const std::string& fragment_source, const char* name) {
    const GLuint vs = compile(GL_VERTEX_SHADER, vertex_source, name);
    const GLuint fs = compile(GL_FRAGMENT_SHADER, fragment_source, name);
    const GLuint program = glCreateProgram();
    glAttachShader(program, vs);
    glAttachShader(program, fs);
    glLinkProgram(program);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        GLint length = 0;
        glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
        std::string log(static_cast<size_t>(length > 0 ? length : 1), '\0');
        glGetProgramInfoLog(program, length, nullptr, log.data());
        glDeleteProgram(program);
        throw ViewerError(std::string("program ") + name + " does not link: " + log);
    }
    return program;
}

const char* fullScreenVertexShader() {
    return R"(#version 330 core
void main() {
    // Vertices (-1,-1), (3,-1), (-1,3): one triangle covering the viewport.
    vec2 p = vec2(float((gl_VertexID & 1) << 2) - 1.0, float((gl_VertexID & 2) << 1) - 1.0);
    gl_Position = vec4(p, 0.0, 1.0);
}
)";
}

Texture& Texture::operator=(Texture&& other) noexcept {
    if (this != &other) {
        reset();
        id_ = other.id_;
        other.id_ = 0;
    }
    return *this;
}

void Texture::reset() {
    if (id_) glDeleteTextures(1, &id_);
    id_ = 0;
}

void Texture::create(GLenum target) {
    reset();
    glGenTextures(1, &id_);
    glBindTexture(target, id_);
    glTexParameteri(target, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(target, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(target, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(target, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

void RenderTarget::ensure(int width, int height, GLenum internal_format) {
    if (fbo_ && width == width_ && height == height_ && internal_format == format_) return;
    reset();
    texture_.create(GL_TEXTURE_2D);
    const GLenum type = internal_format == GL_RGBA8 ? GL_UNSIGNED_BYTE : GL_FLOAT;
    glTexImage2D(GL_TEXTURE_2D, 0, static_cast<GLint>(internal_format), width, height, 0, GL_RGBA, type, nullptr);
    glGenFramebuffers(1, &fbo_);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture_.id(), 0);
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        throw ViewerError("framebuffer incomplete (status 0x" + std::to_string(status) + ")");
    width_ = width;
    height_ = height;
    format_ = internal_format;
}

void RenderTarget::reset() {
    if (fbo_) glDeleteFramebuffers(1, &fbo_);
    fbo_ = 0;
    texture_.reset();
    width_ = height_ = 0;
    format_ = 0;
}

void RenderTarget::bind() const {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glViewport(0, 0, width_, height_);
}

void RenderTarget::readRgba(std::vector<float>& out) const {
    out.resize(static_cast<size_t>(width_) * height_ * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, width_, height_, GL_RGBA, GL_FLOAT, out.data());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
}

void RenderTarget::readRgba8(std::vector<unsigned char>& out) const {
    out.resize(static_cast<size_t>(width_) * height_ * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, out.data());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
}

GLuint emptyVertexArray() {
    static GLuint vao = 0;
    if (!vao) glGenVertexArrays(1, &vao);
    return vao;
}

}  // namespace firelook::viewer::gl
