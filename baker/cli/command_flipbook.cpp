// firelook flipbook PACKAGE [--look L.json] [--frames A-B] --layout L [--grid CxR] -o DIR [--format F]
// Engine flipbooks: every selected frame recombined with one look and packed into the layout's
// atlases (runtime/flipbook), plus DIR/flipbook.json saying what is where, and, for a package baked
// with --fire-probes, the look's probes as raw 3D data (DIR/fire_probes.bin). All or nothing
// (cli/staging_folder.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <nlohmann/json.hpp>
#include <optional>

#include "bake/scene_setup.h"
#include "basis/basis_package.h"
#include "basis/fire_probes.h"
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
#include "world/look_track.h"

namespace firelook::cli {
namespace {

std::pair<int, int> parseGrid(const std::string& text) {
    try {
        return bake::parseSize(text);
    } catch (const std::exception&) {
        throw Error(ErrorCode::InvalidArgument, "--grid '" + text + "' is not CxR (columns x rows)");
    }
}

// The frames' fire probes for the look as one raw float32 file (docs/cli.md, "firelook flipbook"):
// per frame its probes' 9 RGB coefficients, and the sidecar's description of where each frame's
// grid is. Null when no selected frame has probes; a package with some frames only is refused.
nlohmann::ordered_json writeFireProbes(const basis::BasisReader& package, const std::vector<int>& frames,
                                       const Look& look, const std::filesystem::path& file) {
    const basis::BakeDescription& d = package.description();
    const world::ResolvedLook resolved = world::resolveLook(look, d);
    const basis::GridWeights weights = basis::interpolationWeights(d.axes, resolved.extinction);
    std::vector<std::optional<basis::FireProbeTable>> tables;
    for (int frame : frames) tables.push_back(package.loadFireProbes(frame));
    const auto missing = std::find(tables.begin(), tables.end(), std::nullopt);
    if (missing == tables.begin() &&
        std::all_of(tables.begin(), tables.end(), [](const auto& t) { return !t; }))
        return nullptr;
    if (missing != tables.end())
        throw Error(ErrorCode::InvalidArgument, package.file().string() + ": frame " +
                                                    std::to_string(frames[missing - tables.begin()]) +
                                                    " has no fire probes, other frames have");
    std::vector<float> data;
    nlohmann::ordered_json grids = nlohmann::ordered_json::array();
    for (size_t n = 0; n < frames.size(); ++n) {
        const int frame = frames[n];
        const basis::FireProbeTable* table = &*tables[n];
        const basis::FireProbeGrid& g = table->grid;
        std::vector<Rgb> values(static_cast<size_t>(g.probes()) * basis::kFireProbeCoefficients);
        basis::evaluateFireProbes(*table, weights, resolved.rbf, values.data());
        grids.push_back({{"frame", frame},
                         {"offset_floats", data.size()},
                         {"counts", {g.counts.x, g.counts.y, g.counts.z}},
                         {"origin", {g.origin.x, g.origin.y, g.origin.z}},
                         {"spacing", {g.spacing.x, g.spacing.y, g.spacing.z}},
                         {"falloff_centre", {g.falloff_centre.x, g.falloff_centre.y, g.falloff_centre.z}},
                         {"falloff_radius", g.falloff_radius}});
        for (const Rgb& v : values) data.insert(data.end(), {v.r, v.g, v.b});
    }
    std::string bytes(data.size() * sizeof(float), '\0');
    std::memcpy(bytes.data(), data.data(), bytes.size());  // little-endian, as every supported machine
    writeFileAtomically(file, bytes);
    return {{"file", file.filename().string()},
            {"encoding",
             "float32 little-endian, per frame at offset_floats: probe p = i + counts[0] (j + counts[1] "
             "k) at origin + spacing * (i, j, k), then its 9 real SH coefficients (Y00, Y1-1, Y10, Y11, "
             "Y2-2, Y2-1, Y20, Y21, Y22), then R, G, B: a 3D texture of counts texels with 27 floats each"},
            {"meaning",
             "radiance arriving from the fire for the look; fluence sqrt(4 pi) L00, irradiance on a "
             "surface facing n sum_l A_l sum_m L_lm Y_lm(n), A = (pi, 2 pi / 3, pi / 4); between probes "
             "blend p * s(p) trilinearly and divide by s(x), s = |x - falloff_centre|^2 + "
             "falloff_radius^2 (firelook.h, fl_fire_probes_sample)"},
            {"frames", grids}};
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
        if (nlohmann::ordered_json probes =
                writeFireProbes(package, frames, look, staging / "fire_probes.bin");
            !probes.is_null())
            sidecar["fire_probes"] = probes;
        writeFileAtomically(staging / "flipbook.json", sidecar.dump(2) + "\n");
        throwIfInterrupted();
        staging.commit();
        bar.finish(std::to_string(frames.size()) + " frames");
        std::printf("wrote %zu atlases of %zu frames (%dx%d grid of %dx%d) and flipbook.json to %s\n", atlases.size(),
                    frames.size(), columns, rows, d.width, d.height, args->out.c_str());
    });
}

}  // namespace firelook::cli
