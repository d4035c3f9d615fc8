#include "look_resolution.h"

#include "fl_check.h"
#include "look/look.h"
#include "world/keyframe_bracket.h"

namespace firelook::viewer {
namespace {

TemperatureBins binsOf(const fl_package_info& info) {
    TemperatureBins bins;
    bins.t_lo = info.temperature_lo;
    bins.t_hi = info.temperature_hi;
    bins.count = info.bin_count;
    return bins;
}

}  // namespace

std::vector<Rgb3> resolveBins(const LookEdit& look, const fl_package_info& info) {
    try {
        std::vector<Rgb3> out;
        for (const Rgb& e : resolveBinEmissivity(parseLook(lookEditToJson(look), "look"), binsOf(info)))
            out.push_back({e.r, e.g, e.b});
        return out;
    } catch (const std::exception& e) {
        throw ViewerError(e.what());
    }
}

double binCentre(const fl_package_info& info, int bin) { return binsOf(info).center(bin); }

std::string keyedLookJson(const std::vector<Keyframe>& keys, double frame_position, const fl_package_info& info) {
    if (keys.empty()) throw ViewerError("no keyframes");
    const runtime::KeyframeBracket bracket = runtime::bracketKeyframes(keys, frame_position);
    if (bracket.lo == bracket.hi) return lookEditToJson(keys[bracket.lo].look);
    try {
        const Look a = parseLook(lookEditToJson(keys[bracket.lo].look), "key");
        const Look b = parseLook(lookEditToJson(keys[bracket.hi].look), "key");
        return lookToJson(interpolateLooks(a, b, bracket.t, binsOf(info)));
    } catch (const std::exception& e) {
        throw ViewerError(e.what());
    }
}

}  // namespace firelook::viewer
