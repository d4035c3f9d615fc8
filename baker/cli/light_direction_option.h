// --light-dir X,Y,Z and --light-irradiance R,G,B, which `render` and `reference` share: one
// directional light chosen at run time in place of the six-way lights (basis/relight.h).
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <vector>

#include "basis/relight.h"

namespace firelook::cli {

struct LightDirectionFlags {
    std::vector<double> direction;                  // empty: not given
    std::vector<double> irradiance{1.0, 1.0, 1.0};  // RGB
};

// Adds both options to `command`; `what` ends --light-dir's help (how the command uses the light).
void addLightDirectionFlags(CLI::App& command, LightDirectionFlags& flags, const std::string& what);

// The light the flags give, nullopt without --light-dir. An InvalidArgument Error naming the flag for
// a zero or non-finite direction or a negative or non-finite irradiance.
std::optional<basis::RunTimeLight> runTimeLight(const CLI::App& command, const LightDirectionFlags& flags);

}  // namespace firelook::cli
