// Fuzz target: bytes -> firelook::parseLook -> resolveBinEmissivity / makeLookModel for several bin
// layouts (1, 3, 16 and 64 bins; tiny, unit and huge temperature units).
//
// Contract checked: parseLook throws only LookError, naming the source; a look that parses
// round-trips through lookToJson; a look model built from it has finite, non-negative emission
// coefficients, a finite emission and extinction at any temperature, and unit light directions.
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_support.h"
#include "look/emission_fit.h"
#include "look/look.h"

namespace {

using namespace firelook;
constexpr const char* kTarget = "fuzz_look_file";
constexpr const char* kSource = "fuzz-look.json";

bool finite(const Rgb& c) { return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b); }

void checkModel(const Look& look, const TemperatureBins& bins) {
    std::vector<glm::dvec3> directions;
    for (std::size_t l = 0; l < look.light_irradiance.size(); ++l)
        directions.push_back({0.3 * double(l) - 0.5, -1.0, 0.25});
    LookModel model;
    try {
        const std::vector<Rgb> emissivity = resolveBinEmissivity(look, bins);
        if (static_cast<int>(emissivity.size()) != bins.count) fuzz::fail(kTarget, "wrong emissivity count");
        model = makeLookModel(look, bins, kDefaultRbfWidth, directions);
    } catch (const LookError& e) {
        if (!fuzz::contains(e.what(), kSource)) fuzz::fail(kTarget, std::string("error without source: ") + e.what());
        return;
    } catch (const EmissionFitError&) {
        // A resolved emissivity that is not finite (a huge preset scale times a ramp): refused.
        return;
    }
    for (const Rgb& c : model.emission.coefficients)
        if (!finite(c) || c.r < 0.0f || c.g < 0.0f || c.b < 0.0f)
            fuzz::fail(kTarget, "emission coefficient not finite or negative");
    for (const double u : {-1.0, 0.0, 0.13, 0.5, 0.77, 1.0, 2.0}) {
        const double t = bins.t_lo + u * (bins.t_hi - bins.t_lo);
        const Rgb e = model.emission.evaluate(t);
        if (!finite(e) || e.r < 0.0f || e.g < 0.0f || e.b < 0.0f) fuzz::fail(kTarget, "L_e not finite or negative");
        if (!std::isfinite(model.sigmaT(1.0, t))) fuzz::fail(kTarget, "sigma_t not finite");
    }
    for (const DirectionalLight& light : model.lights) {
        const double length = std::sqrt(light.direction.x * light.direction.x + light.direction.y * light.direction.y +
                                         light.direction.z * light.direction.z);
        if (!(std::abs(length - 1.0) < 1e-9) || !finite(light.irradiance)) fuzz::fail(kTarget, "bad light");
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    Look look;
    try {
        look = parseLook(text, kSource);
    } catch (const LookError& e) {
        if (!fuzz::contains(e.what(), kSource)) fuzz::fail(kTarget, std::string("error without source: ") + e.what());
        return 0;
    }
    // parseLook(lookToJson(l)) gives l back exactly (look.h).
    const std::string json = lookToJson(look);
    try {
        if (lookToJson(parseLook(json, kSource)) != json) fuzz::fail(kTarget, "lookToJson does not round-trip");
    } catch (const LookError& e) {
        fuzz::fail(kTarget, std::string("lookToJson output does not parse: ") + e.what());
    }
    for (const int n : {1, 3, 16, 64}) {
        checkModel(look, {0.0, 3.0, n});
        checkModel(look, {1.0, 1.001, n});
        checkModel(look, {-2.0e4, 1.0e4, n});
    }
    return 0;
}
