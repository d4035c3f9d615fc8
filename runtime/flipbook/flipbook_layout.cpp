#include "flipbook/flipbook_layout.h"

#include <stdexcept>

#include "basis/six_way_lights.h"
#include "common/error.h"

namespace firelook::flipbook {

Layout parseLayout(std::string_view name) {
    if (name == "six-way-unity") return Layout::SixWayUnity;
    if (name == "six-way-rlt-bbf") return Layout::SixWayRltBbf;
    if (name == "rgba") return Layout::Rgba;
    throw Error(ErrorCode::InvalidArgument,
                "--layout '" + std::string(name) + "' is not six-way-unity, six-way-rlt-bbf or rgba");
}

std::string_view layoutName(Layout layout) {
    switch (layout) {
        case Layout::SixWayUnity: return "six-way-unity";
        case Layout::SixWayRltBbf: return "six-way-rlt-bbf";
        case Layout::Rgba: return "rgba";
    }
    return "rgba";
}

std::vector<AtlasSpec> atlasesOf(Layout layout) {
    using L = Layer;
    const AtlasSpec emission{"emission", {L::EmissionR, L::EmissionG, L::EmissionB, L::Transparency}};
    switch (layout) {
        case Layout::SixWayUnity:
            return {{"six_way_a", {L::Light0, L::Light1, L::Light2, L::Transparency}},
                    {"six_way_b", {L::Light3, L::Light4, L::Light5, L::Emission}},
                    emission};
        case Layout::SixWayRltBbf:
            return {{"rlt", {L::Light0, L::Light3, L::Light1, L::Transparency}},
                    {"bbf", {L::Light4, L::Light2, L::Light5, L::Emission}},
                    emission};
        case Layout::Rgba:
            return {{"rgba", {L::ColourR, L::ColourG, L::ColourB, L::Transparency}}};
    }
    return {};
}

bool usesSixWayLights(Layout layout) { return layout != Layout::Rgba; }

std::string_view layerName(Layer layer) {
    const int index = static_cast<int>(layer);
    if (index < basis::kSixWayLightCount) return basis::kSixWayLightNames[index];
    switch (layer) {
        case Layer::Transparency: return "transparency";
        case Layer::Emission: return "emission";
        case Layer::EmissionR: return "emission_r";
        case Layer::EmissionG: return "emission_g";
        case Layer::EmissionB: return "emission_b";
        case Layer::ColourR: return "colour_r";
        case Layer::ColourG: return "colour_g";
        case Layer::ColourB: return "colour_b";
        default: return "";
    }
}

}  // namespace firelook::flipbook
