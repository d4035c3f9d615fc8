#pragma once

#include <filesystem>
#include <functional>
#include <string>

namespace firelook::vdb {

// The plausible range of the data, in one place. A value beyond it is not a simulation's output but
// a broken export or a unit mix-up (density in the wrong units, a temperature of 1e30 where the
// rest of the cache says 300-3000 K), and it would silently ruin everything downstream: the
// temperature bins are fitted to the data's range, so one such voxel squeezes every real
// temperature into the first bin, and a density of 1e30 makes every voxel next to it an opaque wall
// whose cost and precision the tracers can only just survive. Real caches stay orders of magnitude
// inside: densities are ~0-10 per unit (Blender's ~0-1, the bundled sample <= 1), temperatures at
// most a few thousand (Kelvin) or a few units (Blender's normalised heat). Beyond the bounds loading
// stops with an error naming the file, the grid and the value, unless ReadOptions::clamp_extreme.
inline constexpr double kMaxPlausibleDensity = 1e6;      // per unit density (values above it)
inline constexpr double kMaxPlausibleTemperature = 1e6;  // |T| in the data's units, after the mapping

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
    // The density used everywhere downstream is density_scale * raw (another solver's density units).
    double density_scale = 1.0;
    NonFinitePolicy non_finite = NonFinitePolicy::Clean;
    // Values beyond kMaxPlausibleDensity / kMaxPlausibleTemperature: false refuses the frame (VdbError
    // naming the file, the grid and the value); true clamps them to the bound, counts them in
    // VolumeFrame and reports them like cleaned values (`--clamp-extreme`).
    bool clamp_extreme = false;
    // `--strict`: any gap in the frame numbers, any cleaned value (as under NonFinitePolicy::Refuse)
    // and any clamped value is an error instead of a warning.
    bool strict = false;
    // Receives one line (no trailing newline) per finding that does not stop the read: a gap in the
    // frame numbers when the sequence is opened (VdbSequence::open), the values cleaned or clamped
    // in one grid of one frame when it is loaded (cleaningReport), frames a selection skips. May be
    // called from the threads that call VdbSequence::load. Empty: silent.
    std::function<void(const std::string& message)> warn{};
    // Called by VdbSequence::load before it reads a frame's file; may throw to abandon the read
    // (the CLI throws there once SIGINT/SIGTERM arrived, so loading many frames stops between two).
    std::function<void(const std::filesystem::path& file)> before_load{};
};

}  // namespace firelook::vdb
