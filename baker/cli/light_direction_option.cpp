#include "cli/light_direction_option.h"

#include <stdexcept>

#include "common/error.h"

namespace firelook::cli {

void addLightDirectionFlags(CLI::App& command, LightDirectionFlags& flags, const std::string& what) {
    command.add_option("--light-dir", flags.direction,
                       "X,Y,Z: a directional light travelling along this world-space direction, " + what)
        ->expected(3)
        ->delimiter(',');
    command.add_option("--light-irradiance", flags.irradiance, "R,G,B: the --light-dir light's irradiance")
        ->expected(3)
        ->delimiter(',')
        ->capture_default_str();
}

std::optional<basis::RunTimeLight> runTimeLight(const CLI::App& command, const LightDirectionFlags& flags) {
    if (command.count("--light-dir") == 0) {
        if (command.count("--light-irradiance") > 0)
            throw Error(ErrorCode::InvalidArgument, "--light-irradiance needs --light-dir");
        return std::nullopt;
    }
    basis::RunTimeLight light;
    light.direction = {flags.direction[0], flags.direction[1], flags.direction[2]};
    light.irradiance = {flags.irradiance[0], flags.irradiance[1], flags.irradiance[2]};
    try {
        basis::checkedUnitDirection(light);
    } catch (const Error& e) {
        throw Error(e.code(), std::string("--light-dir / --light-irradiance: ") + e.what());
    }
    return light;
}

}  // namespace firelook::cli
