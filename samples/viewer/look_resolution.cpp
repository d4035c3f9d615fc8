#include "look_resolution.h"

#include "fl_check.h"

namespace firelook::viewer {

std::vector<Rgb3> resolveBins(const LookEdit& look, fl_package package) {
    const fl_look handle = makeFlLook(look, "look");
    uint32_t count = 0;
    fl_result result = fl_look_get_bin_emissivity(handle, package, nullptr, 0, &count);
    std::vector<float> rgb(3 * size_t{count});
    if (result == FL_OK) result = fl_look_get_bin_emissivity(handle, package, rgb.data(), count, &count);
    const std::string error = fl_last_error();  // fl_look_release would clear it
    fl_look_release(handle);
    if (result != FL_OK) throw ViewerError(error + " (" + fl_result_string(result) + ")");
    std::vector<Rgb3> out;
    for (uint32_t i = 0; i < count; ++i) out.push_back({rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]});
    return out;
}

double binCentre(const fl_package_info& info, int bin) {
    return info.temperature_lo + (bin + 0.5) * ((info.temperature_hi - info.temperature_lo) / info.bin_count);
}

}  // namespace firelook::viewer
