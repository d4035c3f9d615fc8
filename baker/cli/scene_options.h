// Options that `bake` and `reference` share, so the same flags give the same camera.
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <string>

#include "bake/bake_config.h"

namespace firelook::cli {

struct SceneFlags {
    std::string scene;
    std::vector<double> camera;
    std::string size = "256x256";
    std::string up = "y";
    int bins = 16;
    std::string config;
};

// Adds --scene, --camera, --size, --up, --bins and --config to a subcommand.
void addSceneFlags(CLI::App& command, SceneFlags& flags);

// Defaults, then the --config file, then explicit flags (flags win).
bake::BakeConfig makeBakeConfig(const CLI::App& command, const SceneFlags& flags);

}  // namespace firelook::cli
