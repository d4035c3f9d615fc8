#include "cli/light_direction_option.h"

#include <cstdlib>
#include <stdexcept>

#include "common/error.h"

namespace firelook::cli {
namespace {

// "A,B,C" as three numbers (nan and inf parse, so the light's own check names them).
std::array<double, 3> threeNumbers(const std::string& text, const char* flag) {
    std::array<double, 3> v{};
    size_t start = 0;
    for (int i = 0; i < 3; ++i) {
        const size_t comma = i < 2 ? text.find(',', start) : text.size();
        const std::string part =
            comma == std::string::npos ? std::string() : text.substr(start, comma - start);
        char* end = nullptr;
        v[static_cast<size_t>(i)] = part.empty() ? 0.0 : std::strtod(part.c_str(), &end);
        if (part.empty() || end != part.c_str() + part.size())
            throw Error(ErrorCode::InvalidArgument,
                        std::string(flag) + " '" + text + "' is not three numbers A,B,C");
        start = comma + 1;
    }
    return v;
}

}  // namespace

void addLightDirectionFlags(CLI::App& command, LightDirectionFlags& flags, const std::string& what) {
    command
        .add_option("--light-dir", flags.directions,
                    "X,Y,Z: a directional light travelling along this world-space direction, " + what +
                        "; repeat for several lights")
        ->take_all()
        ->allow_extra_args(false);
    command
        .add_option("--light-irradiance", flags.irradiances,
                    "R,G,B: the --light-dir lights' irradiance (default 1,1,1): once for all, or once per "
                    "--light-dir in its order")
        ->take_all()
        ->allow_extra_args(false);
}

std::vector<basis::RunTimeLight> runTimeLights(const LightDirectionFlags& flags) {
    if (flags.directions.empty()) {
        if (!flags.irradiances.empty())
            throw Error(ErrorCode::InvalidArgument, "--light-irradiance needs --light-dir");
        return {};
    }
    if (flags.irradiances.size() > 1 && flags.irradiances.size() != flags.directions.size())
        throw Error(ErrorCode::InvalidArgument, "--light-irradiance given " +
                                                    std::to_string(flags.irradiances.size()) + " times for " +
                                                    std::to_string(flags.directions.size()) +
                                                    " --light-dir: give it once, or once per light");
    std::vector<basis::RunTimeLight> lights;
    for (size_t k = 0; k < flags.directions.size(); ++k) {
        const std::array<double, 3> d = threeNumbers(flags.directions[k], "--light-dir");
        const std::array<double, 3> e =
            flags.irradiances.empty() ? std::array<double, 3>{1.0, 1.0, 1.0}
                                      : threeNumbers(flags.irradiances[flags.irradiances.size() == 1 ? 0 : k],
                                                     "--light-irradiance");
        basis::RunTimeLight light;
        light.direction = {d[0], d[1], d[2]};
        light.irradiance = {static_cast<float>(e[0]), static_cast<float>(e[1]), static_cast<float>(e[2])};
        try {
            basis::checkedUnitDirection(light);
        } catch (const Error& error) {
            throw Error(error.code(), std::string("--light-dir / --light-irradiance: ") + error.what());
        }
        lights.push_back(light);
    }
    return lights;
}

}  // namespace firelook::cli
