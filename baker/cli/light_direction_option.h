// --light-dir X,Y,Z and --light-irradiance R,G,B, which `render` and `reference` share: directional
// lights chosen at run time in place of the six-way or sphere lights (basis/relight.h). Both
// repeat: one --light-dir per light, and either one --light-irradiance for all of them or one per
// --light-dir, in the same order.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "basis/relight.h"

namespace firelook::cli {

struct LightDirectionFlags {
    std::vector<std::string> directions;   // "X,Y,Z" each; empty: not given
    std::vector<std::string> irradiances;  // "R,G,B" each; empty: 1,1,1
};

// Adds both options to `command`; `what` ends --light-dir's help (how the command uses the light).
void addLightDirectionFlags(CLI::App& command, LightDirectionFlags& flags, const std::string& what);

// The lights the flags give, none without --light-dir. An InvalidArgument Error naming the flag for
// text that is not three numbers, a zero or non-finite direction, a negative or non-finite
// irradiance, or a count of --light-irradiance that is neither 1 nor that of --light-dir.
std::vector<basis::RunTimeLight> runTimeLights(const LightDirectionFlags& flags);

}  // namespace firelook::cli
