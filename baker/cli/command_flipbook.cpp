// firelook flipbook PACKAGE [--look L.json] [--frames A-B] --layout L [--grid CxR] -o DIR [--format F]
// Engine flipbooks: every selected frame recombined with one look and packed into the layout's
// atlases (runtime/flipbook), plus DIR/flipbook.json saying what is where. All or nothing
// (cli/staging_folder.h).
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "bake/scene_setup.h"
#include "basis/basis_package.h"
#include "basis/six_way_lights.h"
#include "cli/commands.h"
#include "cli/interrupt.h"
#include "cli/output_option.h"
#include "cli/progress_bar.h"
#include "cli/staging_folder.h"
#include "common/atomic_file.h"
#include "common/error.h"
#include "flipbook/atlas.h"
#include "flipbook/frame_layers.h"
#include "image/image_io.h"
#include "look/look.h"

namespace firelook::cli {
namespace {

std::pair<int, int> parseGrid(const std::string& text) {
    try {
        return bake::parseSize(text);
    } catch (const std::exception&) {
        throw Error(ErrorCode::InvalidArgument, "--grid '" + text + "' is not CxR (columns x rows)");
    }
}

}  // namespace

void registerFlipbookCommand(CLI::App& app) {
    struct Args {
        std::string package, look, frames, layout, grid, out, format = "exr";
        double fps = 24.0;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = app.add_subcommand("flipbook", "Engine flipbook atlases (six-way lightmaps or RGBA) of a package");
    cmd->add_option("PACKAGE", args->package, ".firelook package")->required()->check(CLI::ExistingFile);
    cmd->add_option("--look", args->look, "look file (default: the package's); six-way layouts ignore its lights")
        ->check(CLI::ExistingFile);
    cmd->add_option("--frames", args->frames, "frames A-B,C (default: all)");
    cmd->add_option("--layout", args->layout, "six-way-unity, six-way-rlt-bbf or rgba")
        ->required()
        ->check(CLI::IsMember({"six-way-unity", "six-way-rlt-bbf", "rgba"}));
    cmd->add_option("--grid", args->grid, "atlas grid CxR (default: the squarest that holds the frames)");
    addOutputOption(*cmd, args->out, "output folder")->required();
    cmd->add_option("--format", args->format, "exr (half, values as they are) or png / tga (8 bits, normalised)")
        ->check(CLI::IsMember({"exr", "png", "tga"}))
        ->capture_default_str();
    cmd->add_option("--fps", args->fps, "frame rate recorded in the sidecar")->check(CLI::PositiveNumber)->capture_default_str();
    cmd->callback([args] {
        const basis::BasisReader package = basis::BasisReader::open(args->package);
        const basis::BakeDescription& d = package.description();
        const flipbook::Layout layout = flipbook::parseLayout(args->layout);
        const bool six_way = flipbook::usesSixWayLights(layout);
        if (six_way && d.six_way_first_light < 0)
            throw Error(ErrorCode::InvalidArgument,
                        args->package + ": baked without six-way lights; layout " + args->layout +
                            " needs them (firelook bake --lights six-way)");
        const Look look = args->look.empty() ? parseLook(d.default_look_json, args->package + " (default look)")
                                             : loadLook(args->look);
        const auto ranges = bake::parseFrameRanges(args->frames);
        std::vector<int> frames;
        for (const basis::FrameRecord& r : d.frames)
            if (ranges.empty() || std::any_of(ranges.begin(), ranges.end(), [&](const auto& range) {
                    return r.frame >= range.first && r.frame <= range.second;
                }))
                frames.push_back(r.frame);
        if (frames.empty())
            throw Error(ErrorCode::InvalidArgument,
                        args->package + ": no frame in --frames '" + args->frames + "'");
        int columns = static_cast<int>(std::ceil(std::sqrt(double(frames.size()))));
        int rows = static_cast<int>((frames.size() + columns - 1) / columns);
        if (!args->grid.empty()) std::tie(columns, rows) = parseGrid(args->grid);
        if (static_cast<size_t>(columns) * rows < frames.size())
            throw Error(ErrorCode::InvalidArgument,
                        "--grid " + args->grid + " holds " + std::to_string(columns * rows) +
                            " frames, fewer than the " + std::to_string(frames.size()) + " selected");

        std::vector<flipbook::FrameLayers> layers;
        ProgressBar bar("flipbook");
        for (size_t n = 0; n < frames.size(); ++n) {
            throwIfInterrupted();
            const basis::ResidentFrame resident = package.loadResidentFrame(frames[n], std::pmr::get_default_resource());
            layers.push_back(flipbook::renderFrameLayers(d, resident, look, six_way));
            bar.update(double(n + 1) / frames.size(), "frame " + std::to_string(frames[n]));
        }
        const bool eight_bit = args->format != "exr";
        const flipbook::Normalisation norm = flipbook::normalisationFor(layers, eight_bit);

        StagingFolder staging(args->out, "flipbook");
        nlohmann::ordered_json atlases = nlohmann::ordered_json::array();
        for (const flipbook::AtlasSpec& spec : flipbook::atlasesOf(layout)) {
            throwIfInterrupted();
            const std::string file = spec.name + "." + args->format;
            image::writeDataImage(staging / file, flipbook::packAtlas(spec, layers, columns, rows, norm));
            nlohmann::ordered_json channels = nlohmann::ordered_json::array();
            for (flipbook::Layer layer : spec.channels) channels.push_back(std::string(flipbook::layerName(layer)));
            atlases.push_back({{"file", file}, {"channels", channels}});
        }
        nlohmann::ordered_json sidecar = {
            {"format", "firelook-flipbook"},
            {"version", 1},
            {"layout", args->layout},
            {"package", std::filesystem::path(args->package).filename().string()},
            {"frames", frames},
            {"frame_rate", args->fps},
            {"grid", {{"columns", columns}, {"rows", rows}, {"order", "row-major, top-left first"}}},
            {"frame_size", {{"width", d.width}, {"height", d.height}}},
            {"atlases", atlases},
            {"encoding", eight_bit ? "8-bit linear (no sRGB curve)" : "half float, linear"},
            {"premultiplied", true},
            {"normalisation",
             {{"lightmap_scale", norm.lightmap_scale},
              {"emission_scale", norm.emission_scale},
              {"meaning", "value = texel * scale; a lightmap value is the radiance per unit irradiance from that "
                          "side (white light), emission and colour are radiance"}}},
            {"look", nlohmann::ordered_json::parse(lookToJson(look))},
        };
        if (six_way) {
            nlohmann::ordered_json names = nlohmann::ordered_json::array();
            for (std::string_view name : basis::kSixWayLightNames) names.push_back(std::string(name));
            sidecar["six_way_lights"] = {
                {"names", names},
                {"frame", "camera: right +X, top +Y, back -Z (far side of the volume), as basis/six_way_lights.h"},
                {"look_lights", "ignored: each lightmap is its light alone, emission is every light off"}};
        }
        writeFileAtomically(staging / "flipbook.json", sidecar.dump(2) + "\n");
        throwIfInterrupted();
        staging.commit();
        bar.finish(std::to_string(frames.size()) + " frames");
        std::printf("wrote %zu atlases of %zu frames (%dx%d grid of %dx%d) and flipbook.json to %s\n", atlases.size(),
                    frames.size(), columns, rows, d.width, d.height, args->out.c_str());
    });
}

}  // namespace firelook::cli
