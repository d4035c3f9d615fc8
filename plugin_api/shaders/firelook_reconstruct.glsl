// firelook_reconstruct.glsl — a FireLook instance's image on the GPU (GLSL 3.30 core or later).
// The viewer (samples/viewer) compiles this very file; an engine can take it as it is.
//
// Compile it as a fragment shader after two lines the host writes:
//     #version 330 core
//     #define MAX_LAYERS n        // n = ceil(fl_package_info.max_rank / 4), at least 1
// It computes, per pixel p (firelook.h, fl_instance_state):
//     rgb(p)   = max(0, sum_k U[p][k] z[k])
//     alpha(p) = mean over the footprint samples s of 1 - exp(-(a O_a(s, p) + b O_b(s, p))),
//     O_a(s, p) = (1 - t) O_a(s, lower)(p) + t O_a(s, upper)(p)
// and writes premultiplied linear RGBA (final = rgb + (1 - alpha) background).
//
// Inputs (every value straight from the C API; "S" = fl_package_info.footprint_samples,
// "T" = alpha_threshold_count, G = ceil(S / 4)):
//   u_factors   sampler2DArray, RGBA16F, width x height x ceil(rank / 4) layers: exactly the buffer of
//               fl_instance_get_frame_u (layer l, channel c = U[p][4 l + c], 0 beyond the rank).
//   u_depths    sampler2DArray, RGBA32F, width x height x G (1 + T) layers: fl_instance_get_frame_depths'
//               single-channel layers regrouped four footprint samples to a texel, so one fetch serves
//               four samples: layer g, channel c = O_b(4 g + c); layer G + j G + g, channel c =
//               O_a(4 g + c, j); samples past S are 0 (u_last_mask drops them).
//   Coefficients  std140 uniform block of 3 MAX_LAYERS vec4: z[3 l + ch] = (z[4 l][ch], z[4 l + 1][ch],
//               z[4 l + 2][ch], z[4 l + 3][ch]) from fl_instance_get_coefficients (z[k * 3 + ch]), 0 beyond
//               the rank.
//   u_layers    int, ceil(fl_instance_state.rank / 4): the layers the frame shown has.
//   u_groups    int, G;  u_samples  int, S;  u_last_mask  vec4, 1 for each of the last group's samples
//               that exist (S - 4 (G - 1) of them), 0 for the padding.
//   u_lower, u_upper, u_t        fl_instance_state.alpha_layer_lower, alpha_layer_upper, alpha_layer_t
//   u_extinction_a, u_extinction_b  fl_instance_state.extinction_a, extinction_b
// Pixels: firelookReconstruct(p) takes the package's pixel (x right, y = 0 the image's top row, as
// every buffer of the C API). The main() below (left out when the host defines FIRELOOK_NO_MAIN, to
// call firelookReconstruct from its own shader) draws the image into a width x height target with
// target row y = image row y, e.g. with a full-screen triangle; flip when displaying it.
// Texel fetches only: no filtering, no mipmaps (set GL_NEAREST anyway for incomplete-texture rules).

uniform sampler2DArray u_factors;
uniform sampler2DArray u_depths;
layout(std140) uniform Coefficients { vec4 z[3 * MAX_LAYERS]; };
uniform int u_layers;
uniform int u_groups;
uniform int u_samples;
uniform int u_lower;
uniform int u_upper;
uniform float u_t;
uniform float u_extinction_a;
uniform float u_extinction_b;
uniform vec4 u_last_mask;

vec4 firelookReconstruct(ivec2 p) {
    vec3 rgb = vec3(0.0);
    for (int l = 0; l < u_layers; ++l) {
        vec4 u = texelFetch(u_factors, ivec3(p, l), 0);
        rgb += vec3(dot(u, z[3 * l]), dot(u, z[3 * l + 1]), dot(u, z[3 * l + 2]));
    }
    float sum = 0.0;
    for (int g = 0; g < u_groups; ++g) {
        vec4 o_b = texelFetch(u_depths, ivec3(p, g), 0);
        vec4 lower = texelFetch(u_depths, ivec3(p, u_groups + u_lower * u_groups + g), 0);
        vec4 upper = texelFetch(u_depths, ivec3(p, u_groups + u_upper * u_groups + g), 0);
        vec4 o_a = (1.0 - u_t) * lower + u_t * upper;
        vec4 tau = u_extinction_a * o_a + u_extinction_b * o_b;
        vec4 mask = g == u_groups - 1 ? u_last_mask : vec4(1.0);
        sum += dot(mask, vec4(1.0) - exp(-max(tau, vec4(0.0))));
    }
    return vec4(max(rgb, vec3(0.0)), sum / float(u_samples));
}

#ifndef FIRELOOK_NO_MAIN
out vec4 out_rgba;

void main() { out_rgba = firelookReconstruct(ivec2(gl_FragCoord.xy)); }
#endif
