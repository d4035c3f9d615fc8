#include "basis/frame_factors.h"

#include <glm/gtc/packing.hpp>

namespace firelook::basis {

std::vector<float> decodeU(const FrameFactors& factors) {
    std::vector<float> u(factors.u_half.size());
    for (size_t i = 0; i < u.size(); ++i) u[i] = glm::unpackHalf1x16(factors.u_half[i]);
    return u;
}

}  // namespace firelook::basis
