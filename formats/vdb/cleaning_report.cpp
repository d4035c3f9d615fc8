// The words for what loading changed in a frame (volume_frame.h): shared by every command's
// warnings, `firelook info` and the errors of --strict.
#include <cstdio>
#include <string>
#include <vector>

#include "vdb/read_options.h"
#include "vdb/volume_frame.h"

namespace firelook::vdb {
namespace {

std::string number(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    return text;
}

// "12 NaN, 0 Inf, 3 negative values" (density) or "12 NaN, 0 Inf values"; empty if none.
std::string cleanedPart(const CleanedValues& c, bool is_density) {
    if (c.nan + c.inf + c.negative == 0) return {};
    std::string text = std::to_string(c.nan) + " NaN, " + std::to_string(c.inf) + " Inf";
    if (is_density) text += ", " + std::to_string(c.negative) + " negative";
    return text + " values";
}

// "5 values above 1e+06" (density) or "5 values beyond +-1e+06"; empty if none.
std::string clampedPart(const CleanedValues& c, bool is_density) {
    if (c.clamped == 0) return {};
    return std::to_string(c.clamped) + (c.clamped == 1 ? " value " : " values ") +
           (is_density ? "above " + number(kMaxPlausibleDensity) : "beyond +-" + number(kMaxPlausibleTemperature));
}

std::string gridReport(const CleanedValues& c, bool is_density) {
    const std::string cleaned = cleanedPart(c, is_density), clamped = clampedPart(c, is_density);
    std::string text;
    if (!cleaned.empty()) text = cleaned + " set to 0";
    if (!clamped.empty())
        text += (text.empty() ? "" : "; ") + clamped + " clamped to " +
                (is_density ? number(kMaxPlausibleDensity) : "+-" + number(kMaxPlausibleTemperature));
    return text;
}

std::string gridSummary(const CleanedValues& c, bool is_density) {
    const std::string cleaned = cleanedPart(c, is_density), clamped = clampedPart(c, is_density);
    if (cleaned.empty()) return clamped;
    return clamped.empty() ? cleaned : cleaned + ", " + clamped;
}

}  // namespace

std::vector<std::string> cleaningReport(const VolumeFrame& frame) {
    std::vector<std::string> lines;
    if (frame.density_cleaned.any())
        lines.push_back(frame.file.string() + ": " + frame.density_stats.name + ": " +
                        gridReport(frame.density_cleaned, true));
    if (frame.temperature_cleaned.any())
        lines.push_back(frame.file.string() + ": " + frame.temperature_stats.name + ": " +
                        gridReport(frame.temperature_cleaned, false));
    return lines;
}

std::string cleaningSummary(const VolumeFrame& frame) {
    std::string text;
    if (frame.density_cleaned.any())
        text = frame.density_stats.name + ": " + gridSummary(frame.density_cleaned, true);
    if (frame.temperature_cleaned.any())
        text += (text.empty() ? "" : "; ") + frame.temperature_stats.name + ": " +
                gridSummary(frame.temperature_cleaned, false);
    return text;
}

}  // namespace firelook::vdb
