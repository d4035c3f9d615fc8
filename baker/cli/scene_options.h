// Options that `bake` and `reference` share, so the same flags give the same camera.
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <string>

#include "bake/bake_config.h"
#include "cli/sequence_options.h"

namespace firelook::cli {

struct SceneFlags {
    std::string scene;
    std::vector<double> camera;
    std::string size = "256x256";
    std::string up = "y";
    int bins = 16;
    std::string config;
    std::string lights = "scene";  // --lights scene|six-way|sphere[:N]
    SequenceFlags sequence;  // --strict, --clamp-extreme
};

// Adds --scene, --camera, --size, --up, --bins, --lights, --config, --strict and --clamp-extreme to a
// subcommand.
void addSceneFlags(CLI::App& command, SceneFlags& flags);

// Defaults, then the --config file, then explicit flags (flags win). config.read carries the
// sequence flags and the warning sink (sequence_options.h), so whatever reads the sequence with it
// (bakePackage, the reference) reports and refuses alike. A quality preset (bake --quality) is
// applied before the file, whose "trace" keys then change single settings of it.
bake::BakeConfig makeBakeConfig(const CLI::App& command, const SceneFlags& flags, const std::string& quality = {});

}  // namespace firelook::cli
