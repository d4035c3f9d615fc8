#pragma once

#include <string>

namespace firelook::vdb {

// What to do with NaN/Inf values and negative densities found in active voxels.
enum class NonFinitePolicy {
    Refuse,  // throw VdbError giving the number of offending voxels
    Clean,   // set them to 0 and count them in VolumeFrame (the default: simulation caches
             // occasionally hold a few such voxels and a bake should not stop for them)
};

struct ReadOptions {
    // Empty means auto-detect from the first frame: density from "density"; temperature from
    // "temperature", then "heat", then "flame". VdbSequence::options() returns the names chosen.
    std::string density_grid{};
    std::string temperature_grid{};
    // The temperature used everywhere downstream is T = temperature_scale * raw + temperature_offset.
    double temperature_scale = 1.0;
    double temperature_offset = 0.0;
    NonFinitePolicy non_finite = NonFinitePolicy::Clean;
};

}  // namespace firelook::vdb
