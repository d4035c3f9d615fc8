#include "look/blackbody.h"

#include <cmath>
#include <glm/common.hpp>

namespace firelook {
namespace {

// Piecewise Gaussian with different spreads left and right of the mean.
double lobe(double lambda_nm, double mean, double sigma_left, double sigma_right) {
    const double t = (lambda_nm - mean) / (lambda_nm < mean ? sigma_left : sigma_right);
    return std::exp(-0.5 * t * t);
}

// Wyman, Sloan & Shirley 2013, equations 2-4 (CIE 1931 2-degree observer).
glm::dvec3 colourMatching(double lambda_nm) {
    const double x = 1.056 * lobe(lambda_nm, 599.8, 37.9, 31.0) + 0.362 * lobe(lambda_nm, 442.0, 16.0, 26.7) -
                     0.065 * lobe(lambda_nm, 501.1, 20.4, 26.2);
    const double y = 0.821 * lobe(lambda_nm, 568.8, 46.9, 40.5) + 0.286 * lobe(lambda_nm, 530.9, 16.3, 31.1);
    const double z = 1.217 * lobe(lambda_nm, 437.0, 11.8, 36.0) + 0.681 * lobe(lambda_nm, 459.0, 26.0, 13.8);
    return {x, y, z};
}

// Planck's law, spectral radiance per metre of wavelength.
double planck(double lambda_m, double kelvin) {
    constexpr double h = 6.62607015e-34;  // J s
    constexpr double c = 2.99792458e8;    // m/s
    constexpr double k = 1.380649e-23;    // J/K
    const double exponent = h * c / (lambda_m * k * kelvin);
    return 2.0 * h * c * c / (std::pow(lambda_m, 5) * std::expm1(exponent));
}

}  // namespace

glm::dvec3 blackbodyXyz(double kelvin) {
    glm::dvec3 xyz(0.0);
    for (int lambda_nm = 360; lambda_nm <= 830; ++lambda_nm)
        xyz += colourMatching(lambda_nm) * planck(lambda_nm * 1e-9, kelvin) * 1e-9;  // d(lambda) = 1 nm
    return xyz;
}

glm::dvec3 xyzToLinearSrgb(const glm::dvec3& xyz) {
    return {3.2404542 * xyz.x - 1.5371385 * xyz.y - 0.4985314 * xyz.z,
            -0.9692660 * xyz.x + 1.8760108 * xyz.y + 0.0415560 * xyz.z,
            0.0556434 * xyz.x - 0.2040259 * xyz.y + 1.0572252 * xyz.z};
}

glm::dvec3 blackbodyColor(double kelvin) {
    const glm::dvec3 xyz = blackbodyXyz(kelvin);
    const glm::dvec3 rgb = xyzToLinearSrgb(xyz / xyz.y);
    return glm::max(rgb, glm::dvec3(0.0));
}

}  // namespace firelook
