#include "look_resolution.h"

#include <algorithm>

#include "fl_check.h"
#include "look/look.h"

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
    size_t hi = 0;
    while (hi < keys.size() && keys[hi].frame <= frame_position) ++hi;
    if (hi == 0 || hi == keys.size() || !(keys[hi].frame > keys[hi - 1].frame))
        return lookEditToJson(keys[hi == 0 ? 0 : hi - 1].look);
    try {
        const Look a = parseLook(lookEditToJson(keys[hi - 1].look), "key");
        const Look b = parseLook(lookEditToJson(keys[hi].look), "key");
        const double t =
            std::clamp((frame_position - keys[hi - 1].frame) / (keys[hi].frame - keys[hi - 1].frame), 0.0, 1.0);
        return lookToJson(interpolateLooks(a, b, t, binsOf(info)));
    } catch (const std::exception& e) {
        throw ViewerError(e.what());
    }
}

}  // namespace firelook::viewer
