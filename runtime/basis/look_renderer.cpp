#include "basis/look_renderer.h"

#include <cmath>
#include <vector>

#include "basis/recombine.h"

namespace firelook::basis {

void checkBakedAlbedo(const BakeDescription& description, const Look& look) {
    if (std::abs(look.albedo - description.albedo) > 1e-6)
        throw LookError(look.source_name + ": key 'albedo': " + std::to_string(look.albedo) +
                        " differs from the package's baked albedo " + std::to_string(description.albedo) +
                        " (albedo is fixed at bake time)");
}

void renderLookImage(const BakeDescription& description, const ResidentFrame& frame, const Look& look,
                     std::span<float> rgba_out) {
    checkBakedAlbedo(description, look);
    const LookModel model = makeLookModel(look, description.bins, description.rbf_width, description.light_directions);
    std::vector<float> z(static_cast<size_t>(frame.rank) * 3);
    const LookWeights weights{look.extinction(), model.emission.coefficients, look.light_irradiance};
    computeCoefficients(description, frame, weights, z);
    reconstructImage(description, frame, z, look.extinction(), rgba_out);
}

}  // namespace firelook::basis
