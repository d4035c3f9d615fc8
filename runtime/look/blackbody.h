// Colour of a blackbody radiator, for the "blackbody" emission preset.
#pragma once

#include <glm/vec3.hpp>

namespace firelook {

// CIE 1931 XYZ of Planck's spectral radiance at `kelvin`, integrated over
// 360..830 nm in 1 nm steps against the multi-lobe Gaussian fit of the colour
// matching functions by Wyman, Sloan and Shirley, "Simple Analytic
// Approximations to the CIE XYZ Color Matching Functions", JCGT 2(2), 2013.
// Absolute scale: W sr^-1 m^-2 (times the CMFs' unitless weights).
glm::dvec3 blackbodyXyz(double kelvin);

// XYZ to linear sRGB primaries with the D65 white (IEC 61966-2-1).
glm::dvec3 xyzToLinearSrgb(const glm::dvec3& xyz);

// Linear sRGB colour of a blackbody at `kelvin`, scaled to luminance Y = 1 and
// with negative components (outside the sRGB gamut, e.g. blue below ~1900 K)
// clipped to zero.
glm::dvec3 blackbodyColor(double kelvin);

}  // namespace firelook
