// The bundled sample's folder (samples/data/explosion), for the suites whose target defines
// FIRELOOK_SAMPLE_DIR.
#pragma once

#include <string>

namespace firelook::testing {

inline const std::string kSample = FIRELOOK_SAMPLE_DIR;

}  // namespace firelook::testing
