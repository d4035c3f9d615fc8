#include "compositor.h"

#include <cmath>

namespace firelook::viewer {
namespace {

const char* kFragmentShader = R"(#version 330 core
uniform sampler2D u_image;  // linear premultiplied RGBA
uniform sampler2D u_other;  // difference mode: the image to compare with
uniform sampler2D u_flare;  // RGB added on top (A = 0)
uniform int u_mode;         // 0: composite, 1: difference
uniform int u_use_flare;
uniform float u_scale;      // 2^exposure, or the difference gain
uniform int u_checker;
uniform int u_checker_pixels;
uniform vec3 u_background_a;
uniform vec3 u_background_b;
out vec4 out_colour;

vec3 linearToSrgb(vec3 c) {
    c = clamp(c, 0.0, 1.0);
    return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 c = texelFetch(u_image, p, 0);
    vec3 colour;
    if (u_mode == 1) {
        colour = abs(c.rgb - texelFetch(u_other, p, 0).rgb) * u_scale;
    } else {
        vec3 light = c.rgb;
        if (u_use_flare == 1) light += texelFetch(u_flare, p, 0).rgb;
        vec3 background = u_background_a;
        if (u_checker == 1 && (((p.x / u_checker_pixels) + (p.y / u_checker_pixels)) & 1) == 1)
            background = u_background_b;
        colour = light * u_scale + (1.0 - c.a) * background;
    }
    out_colour = vec4(linearToSrgb(colour), 1.0);
}
)";

}  // namespace

Compositor::Compositor() { program_ = gl::makeProgram(gl::fullScreenVertexShader(), kFragmentShader, "composite"); }

Compositor::~Compositor() {
    if (program_) glDeleteProgram(program_);
}

void Compositor::composite(const gl::RenderTarget& source, GLuint flare, const DisplaySettings& settings,
                           gl::RenderTarget& target) {
    draw(source, 0, flare, 0, std::exp2(settings.exposure_stops), settings, target);
}

void Compositor::difference(const gl::RenderTarget& a, const gl::RenderTarget& b, float gain,
                            gl::RenderTarget& target) {
    draw(a, b.texture(), 0, 1, gain, DisplaySettings{}, target);
}

void Compositor::draw(const gl::RenderTarget& source, GLuint other, GLuint flare, int mode, float scale,
                      const DisplaySettings& s, gl::RenderTarget& target) {
    target.ensure(source.width(), source.height(), GL_RGBA8);
    target.bind();
    glDisable(GL_BLEND);
    glDisable(GL_SCISSOR_TEST);
    glUseProgram(program_);
    glUniform1i(glGetUniformLocation(program_, "u_image"), 0);
    glUniform1i(glGetUniformLocation(program_, "u_other"), 1);
    glUniform1i(glGetUniformLocation(program_, "u_flare"), 2);
    glUniform1i(glGetUniformLocation(program_, "u_mode"), mode);
    glUniform1i(glGetUniformLocation(program_, "u_use_flare"), flare != 0 ? 1 : 0);
    glUniform1f(glGetUniformLocation(program_, "u_scale"), scale);
    glUniform1i(glGetUniformLocation(program_, "u_checker"), s.checker ? 1 : 0);
    glUniform1i(glGetUniformLocation(program_, "u_checker_pixels"), s.checker_pixels > 0 ? s.checker_pixels : 16);
    const Rgb3& a = s.checker ? s.checker_dark : s.solid;
    glUniform3f(glGetUniformLocation(program_, "u_background_a"), a[0], a[1], a[2]);
    glUniform3f(glGetUniformLocation(program_, "u_background_b"), s.checker_light[0], s.checker_light[1],
                s.checker_light[2]);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, source.texture());
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, other);
    glActiveTexture(GL_TEXTURE2);
    glBindTexture(GL_TEXTURE_2D, flare);
    glBindVertexArray(gl::emptyVertexArray());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    for (GLenum unit : {GL_TEXTURE2, GL_TEXTURE1, GL_TEXTURE0}) {
        glActiveTexture(unit);
        glBindTexture(GL_TEXTURE_2D, 0);
    }
    glUseProgram(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void uploadRgba8(const std::vector<unsigned char>& rgba, int width, int height, gl::RenderTarget& target) {
    target.ensure(width, height, GL_RGBA8);
    glBindTexture(GL_TEXTURE_2D, target.texture());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    glBindTexture(GL_TEXTURE_2D, 0);
}

}  // namespace firelook::viewer
