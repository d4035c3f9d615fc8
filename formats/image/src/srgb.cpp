#include "image/srgb.h"

#include <algorithm>
#include <cmath>

namespace firelook::image {

// The piecewise curve of IEC 61966-2-1: a linear toe below the breakpoint, a 2.4 power above it.
double linearToSrgb(double linear) {
    const double x = std::clamp(linear, 0.0, 1.0);
    return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
}

double srgbToLinear(double encoded) {
    const double v = std::clamp(encoded, 0.0, 1.0);
    return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

}  // namespace firelook::image
