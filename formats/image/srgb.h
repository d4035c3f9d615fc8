// The sRGB transfer function (IEC 61966-2-1) used for 8-bit PNG output and input.
#pragma once

namespace firelook::image {

// Linear value in [0, 1] to its sRGB encoding in [0, 1]; inputs outside [0, 1] are clamped first.
double linearToSrgb(double linear);

// sRGB encoding in [0, 1] to a linear value in [0, 1]; inputs outside [0, 1] are clamped first.
double srgbToLinear(double encoded);

}  // namespace firelook::image
