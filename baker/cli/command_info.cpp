// firelook info PATH [--json]: a package (format version, sections, frames,
// image size, rank per frame, everything needed to reproduce an image) or a VDB
// sequence (frames, grids, value ranges, active voxels, bounds).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory_resource>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>

#include "basis/basis_package.h"
#include "cli/commands.h"
#include "cli/sequence_options.h"
#include "common/error.h"
#include "package/container_reader.h"
#include "vdb/vdb_sequence.h"
#include "vdb/volume_frame.h"
#include "world/package.h"

namespace firelook::cli {
namespace {

using nlohmann::ordered_json;

std::string fourcc(uint32_t type) {
    std::string s(4, ' ');
    for (int i = 0; i < 4; ++i) {
        const char c = static_cast<char>((type >> (8 * i)) & 0xff);
        s[i] = (c >= 32 && c < 127) ? c : '?';
    }
    return s;
}

bool looksLikePackage(const std::filesystem::path& path) {
    if (!std::filesystem::is_regular_file(path)) return false;
    if (path.extension() == ".firelook") return true;
    std::ifstream in(path, std::ios::binary);
    char head[4] = {};
    in.read(head, 4);
    return in.gcount() == 4 && static_cast<unsigned char>(head[0]) == 0x89 && head[1] == 'F' && head[2] == 'L' &&
           head[3] == 'K';
}

// The package as the runtime plays it, with its default look and that look's grid weights; none for
// a package the runtime cannot play (the rest of info still describes it).
struct DefaultLookView {
    std::shared_ptr<const world::Package> package;
    basis::GridWeights weights;
    const world::ResolvedLook& look() const { return package->resolvedDefaultLook(); }
};
std::optional<DefaultLookView> defaultLookView(const std::filesystem::path& path) {
    try {
        std::shared_ptr<const world::Package> p = world::Package::open(path);
        basis::GridWeights weights =
            basis::interpolationWeights(p->description().axes, p->resolvedDefaultLook().extinction);
        return DefaultLookView{std::move(p), weights};
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

// The frames' fire lights (basis/fire_lights.h) for the package's default look, all that are stored;
// null for a package without them.
ordered_json fireLightsInfo(const DefaultLookView& view) {
    const world::Package* p = view.package.get();
    const world::ResolvedLook& look = view.look();
    const basis::GridWeights& weights = view.weights;
    ordered_json frames = ordered_json::array();
    int stored = 0;
    for (int slot = 0; slot < p->frameCount(); ++slot) {
        const basis::FireLightTable* table = p->fireLights(slot);
        if (!table) continue;
        stored = table->clusters;
        std::vector<basis::FireLight> lights(table->clusters);
        basis::evaluateFireLights(*table, weights, look.rbf, table->clusters, lights.data());
        ordered_json list = ordered_json::array();
        for (const basis::FireLight& l : lights)
            list.push_back({{"position", {l.position.x, l.position.y, l.position.z}},
                            {"intensity", {l.intensity.r, l.intensity.g, l.intensity.b}},
                            {"radius", l.radius}});
        frames.push_back({{"frame", p->frameNumber(slot)}, {"lights", list}});
    }
    if (frames.empty()) return nullptr;
    return {{"stored_per_frame", stored},
            {"look", "default"},
            {"units", "world space; intensity: radiant intensity (radiance x world area), fluence I / d^2; "
                      "radius: RMS distance of the power from position (firelook.h, fl_fire_light)"},
            {"frames", frames}};
}

// The frames' fire probes (basis/fire_probes.h) for the package's default look: the grid's placement
// and every probe's 9 RGB SH coefficients; null for a package without them.
ordered_json fireProbesInfo(const DefaultLookView& view) {
    const world::Package* p = view.package.get();
    const world::ResolvedLook& look = view.look();
    const basis::GridWeights& weights = view.weights;
    ordered_json frames = ordered_json::array();
    for (int slot = 0; slot < p->frameCount(); ++slot) {
        const basis::FireProbeTable* table = p->fireProbes(slot);
        if (!table) continue;
        const basis::FireProbeGrid& g = table->grid;
        std::vector<Rgb> values(static_cast<size_t>(g.probes()) * basis::kFireProbeCoefficients);
        basis::evaluateFireProbes(*table, weights, look.rbf, values.data());
        ordered_json probes = ordered_json::array();
        for (int probe = 0; probe < g.probes(); ++probe) {
            ordered_json sh = ordered_json::array();
            for (int k = 0; k < basis::kFireProbeCoefficients; ++k) {
                const Rgb& v = values[static_cast<size_t>(probe) * basis::kFireProbeCoefficients + k];
                sh.push_back({v.r, v.g, v.b});
            }
            probes.push_back(sh);
        }
        frames.push_back({{"frame", p->frameNumber(slot)},
                          {"counts", {g.counts.x, g.counts.y, g.counts.z}},
                          {"origin", {g.origin.x, g.origin.y, g.origin.z}},
                          {"spacing", {g.spacing.x, g.spacing.y, g.spacing.z}},
                          {"falloff_centre", {g.falloff_centre.x, g.falloff_centre.y, g.falloff_centre.z}},
                          {"falloff_radius", g.falloff_radius},
                          {"probes", probes}});
    }
    if (frames.empty()) return nullptr;
    return {{"look", "default"},
            {"units",
             "world space; probes[i + counts[0] (j + counts[1] k)] at origin + spacing * (i, j, k), each 9 "
             "RGB real SH coefficients of the radiance arriving from the fire (order Y00, Y1-1, Y10, Y11, "
             "Y2-2, Y2-1, Y20, Y21, Y22); fluence sqrt(4 pi) L00; blend between probes weighted by "
             "|x - falloff_centre|^2 + falloff_radius^2 (firelook.h, fl_fire_probes)"},
            {"frames", frames}};
}

ordered_json packageInfo(const std::filesystem::path& path) {
    const package::ContainerReader reader = package::ContainerReader::open(path);
    ordered_json info;
    info["kind"] = "package";
    info["file"] = path.string();
    info["format_version"] = std::to_string(reader.version().major) + "." + std::to_string(reader.version().minor);
    info["file_bytes"] = reader.fileSize();
    ordered_json sections = ordered_json::array();
    for (const package::SectionInfo& s : reader.sections()) {
        sections.push_back({{"type", fourcc(s.type)},
                            {"frame", s.frame == package::kNoFrame ? ordered_json(nullptr) : ordered_json(s.frame)},
                            {"codec", s.codec == package::Codec::Zstd ? "zstd" : "raw"},
                            {"stored_bytes", s.stored_size},
                            {"raw_bytes", s.raw_size},
                            {"required", s.required()}});
    }
    info["sections"] = sections;
    // Stored bytes by section kind and by frame (what a streaming engine holds per frame).
    std::map<std::string, uint64_t> by_kind;
    std::map<uint32_t, uint64_t> by_frame;
    for (const package::SectionInfo& s : reader.sections()) {
        by_kind[fourcc(s.type)] += s.stored_size;
        if (s.frame != package::kNoFrame) by_frame[s.frame] += s.stored_size;
    }
    ordered_json kinds = ordered_json::object(), frames = ordered_json::array();
    for (const auto& [kind, bytes] : by_kind) kinds[kind] = bytes;
    for (const auto& [frame, bytes] : by_frame) frames.push_back({{"frame", frame}, {"stored_bytes", bytes}});
    info["bytes_by_kind"] = kinds;
    info["bytes_by_frame"] = frames;
    if (const std::optional<std::string> meta = reader.metadata()) {
        const ordered_json doc = ordered_json::parse(*meta, nullptr, false);
        // A package's metadata is JSON (docs/package-format.md); anything else is damage to report, not
        // to describe around.
        if (doc.is_discarded())
            throw Error(ErrorCode::Corrupt,
                        path.string() + ": the metadata section (META) is not valid JSON");
        info["metadata"] = doc;
        // What each frame was baked from, for a pipeline that checks whether a package is up to
        // date: its input file's XXH3-64 (`xxhsum -H3`) and the hash of the settings it was baked with.
        const ordered_json::json_pointer sources("/provenance/sources"), settings("/provenance/settings_xxh3_64");
        if (doc.contains(sources) && doc.contains(settings)) {
            ordered_json inputs = ordered_json::array();
            for (const ordered_json& s : doc.at(sources))
                inputs.push_back({{"frame", s.value("frame", 0)},
                                  {"file", s.value("file", "")},
                                  {"xxh3_64", s.value("xxh3_64", "")},
                                  {"settings_xxh3_64", doc.at(settings)}});
            info["inputs"] = inputs;
        }
    }
    // Opened once, as the runtime plays it, for both; a package it cannot play has neither.
    if (const std::optional<DefaultLookView> view = defaultLookView(path)) {
        if (ordered_json lights = fireLightsInfo(*view); !lights.is_null()) info["fire_lights"] = lights;
        if (ordered_json probes = fireProbesInfo(*view); !probes.is_null()) info["fire_probes"] = probes;
    }
    return info;
}

ordered_json sequenceInfo(const std::string& source, const SequenceFlags& flags) {
    vdb::ReadOptions options;
    applySequenceFlags(flags, options);
    const vdb::VdbSequence sequence = vdb::VdbSequence::open(source, options);
    ordered_json info;
    info["kind"] = "vdb-sequence";
    info["source"] = source;
    info["density_grid"] = sequence.options().density_grid;
    info["temperature_grid"] = sequence.options().temperature_grid;
    info["frame_count"] = sequence.frames().size();
    info["gaps"] = sequence.gaps();
    const vdb::Aabb& b = sequence.sequenceWorldBounds();
    info["world_bounds"] = {{"min", {b.min.x, b.min.y, b.min.z}}, {"max", {b.max.x, b.max.y, b.max.z}}};
    ordered_json frames = ordered_json::array();
    for (const vdb::FrameFile& file : sequence.frames()) {
        const vdb::VolumeFrame f = sequence.load(file.number);
        const auto stats = [](const vdb::GridStats& s) {
            return ordered_json{{"name", s.name}, {"min", s.min}, {"max", s.max}, {"active_voxels", s.active_voxels}};
        };
        ordered_json frame = {{"frame", f.number},
                              {"file", f.file.filename().string()},
                              {"grids", f.all_grid_names},
                              {"density", stats(f.density_stats)},
                              {"temperature", stats(f.temperature_stats)},
                              {"voxel_size", f.voxel_size}};
        if (!f.index_bounds.empty())
            frame["index_bounds"] = {{f.index_bounds.min.x, f.index_bounds.min.y, f.index_bounds.min.z},
                                     {f.index_bounds.max.x, f.index_bounds.max.y, f.index_bounds.max.z}};
        if (f.density_cleaned.any() || f.temperature_cleaned.any()) {
            const auto counts = [](const vdb::CleanedValues& c) {
                return ordered_json{{"nan", c.nan}, {"inf", c.inf}, {"negative", c.negative}, {"clamped", c.clamped}};
            };
            frame["cleaned"] = {{"non_finite", f.cleaned_non_finite},
                                {"negative_density", f.cleaned_negative_density},
                                {"density", counts(f.density_cleaned)},
                                {"temperature", counts(f.temperature_cleaned)},
                                {"summary", vdb::cleaningSummary(f)},
                                {"report", vdb::cleaningReport(f)}};
        }
        frames.push_back(frame);
    }
    info["frames"] = frames;
    return info;
}

void printPackage(const ordered_json& info) {
    std::printf("package %s\n  format version %s, %llu bytes\n", info["file"].get<std::string>().c_str(),
                info["format_version"].get<std::string>().c_str(),
                static_cast<unsigned long long>(info["file_bytes"].get<uint64_t>()));
    if (info.contains("metadata") && info["metadata"].contains("bake")) {
        const ordered_json& bake = info["metadata"]["bake"];
        const ordered_json& bins = bake["temperature_bins"];
        std::printf("  image %dx%d, %d bins over [%g, %g], rbf width %g dT, albedo %g, %zu light(s)\n",
                    bake["width"].get<int>(), bake["height"].get<int>(), bins["count"].get<int>(),
                    bins["t_lo"].get<double>(), bins["t_hi"].get<double>(), bake["rbf_width"].get<double>(),
                    bake["albedo"].get<double>(), bake["light_directions"].size());
        const ordered_json& meta = info["metadata"];
        for (const char* axis : {"temperature_threshold", "smoke_extinction", "flame_extinction"}) {
            // A collapsed axis says what was asked for and why one sample stands for it (axis_collapse.h).
            std::string collapsed;
            if (meta.contains("axis_collapse"))
                for (const ordered_json& c : meta["axis_collapse"]["collapsed"])
                    if (c["axis"] == axis) {
                        char text[160];
                        std::snprintf(text, sizeof text, "  (collapsed from %zu samples %g..%g: they change sigma_t by at most %.2g)",
                                      c["requested"].size(), c["requested"].front().get<double>(),
                                      c["requested"].back().get<double>(), c["relative_change"].get<double>());
                        collapsed = text;
                    }
            std::printf("  %-22s %s%s\n", axis, bake["axes"][axis].dump().c_str(), collapsed.c_str());
        }
        // Recorded only when the map is not the identity (bake/axis_derivation.h).
        if (meta.contains("axis_derivation")) {
            const ordered_json& d = meta["axis_derivation"];
            std::string which;
            for (const auto& [axis, derived] : d["derived"].items())
                if (derived.get<bool>()) which += (which.empty() ? "" : ", ") + axis;
            std::printf("  look axes from the data: temperatures x%g %+g, extinctions x%g; derived: %s "
                        "(\"axis_derivation\" in --json)\n",
                        d["temperature"]["scale"].get<double>(), d["temperature"]["offset"].get<double>(),
                        d["extinction"]["scale"].get<double>(), which.empty() ? "none (all given)" : which.c_str());
        }
        std::printf("  frames (frame:rank):");
        for (const ordered_json& f : bake["frames"]) std::printf(" %d:%d", f["frame"].get<int>(), f["rank"].get<int>());
        std::printf("\n");
    }
    std::printf("  %-6s %7s %5s %12s %12s\n", "type", "frame", "codec", "stored", "raw");
    for (const ordered_json& s : info["sections"])
        std::printf("  %-6s %7s %5s %12llu %12llu\n", s["type"].get<std::string>().c_str(),
                    s["frame"].is_null() ? "-" : std::to_string(s["frame"].get<uint32_t>()).c_str(),
                    s["codec"].get<std::string>().c_str(),
                    static_cast<unsigned long long>(s["stored_bytes"].get<uint64_t>()),
                    static_cast<unsigned long long>(s["raw_bytes"].get<uint64_t>()));
    std::printf("  stored bytes by kind:");
    for (const auto& [kind, bytes] : info["bytes_by_kind"].items())
        std::printf(" %s %.1f KiB", kind.c_str(), bytes.get<uint64_t>() / 1024.0);
    std::printf("\n");
    if (!info["bytes_by_frame"].empty()) {
        uint64_t total = 0, largest = 0;
        for (const ordered_json& f : info["bytes_by_frame"]) {
            total += f["stored_bytes"].get<uint64_t>();
            largest = std::max(largest, f["stored_bytes"].get<uint64_t>());
        }
        std::printf("  stored bytes per frame: mean %.1f KiB, largest %.1f KiB (%zu frames)\n",
                    total / 1024.0 / info["bytes_by_frame"].size(), largest / 1024.0, info["bytes_by_frame"].size());
    }
    if (info.contains("fire_lights"))
        std::printf("  fire lights: %d per frame in %zu frames (default look's under \"fire_lights\" in --json)\n",
                    info["fire_lights"]["stored_per_frame"].get<int>(), info["fire_lights"]["frames"].size());
    if (info.contains("fire_probes")) {
        const ordered_json& first = info["fire_probes"]["frames"].front();
        std::printf(
            "  fire probes: %dx%dx%d per frame in %zu frames (default look's under \"fire_probes\" in "
            "--json)\n",
            first["counts"][0].get<int>(), first["counts"][1].get<int>(), first["counts"][2].get<int>(),
            info["fire_probes"]["frames"].size());
    }
    if (info.contains("inputs"))
        std::printf("  baked with settings xxh3 %s from %zu frame files (their xxh3 under \"inputs\" in --json)\n",
                    info["inputs"].front()["settings_xxh3_64"].get<std::string>().c_str(), info["inputs"].size());
    std::printf("  (--json prints everything, including provenance, camera, lights and the default look)\n");
}

void printSequence(const ordered_json& info) {
    std::printf("VDB sequence %s: %zu frames, density grid '%s', temperature grid '%s'\n",
                info["source"].get<std::string>().c_str(), info["frames"].size(),
                info["density_grid"].get<std::string>().c_str(), info["temperature_grid"].get<std::string>().c_str());
    if (!info["gaps"].empty()) std::printf("  missing frames: %s\n", info["gaps"].dump().c_str());
    std::printf("  world bounds %s .. %s\n", info["world_bounds"]["min"].dump().c_str(),
                info["world_bounds"]["max"].dump().c_str());
    std::printf("  %6s %10s %10s %10s %10s %10s %10s\n", "frame", "rho max", "rho voxels", "T min", "T max", "T voxels",
                "voxel");
    for (const ordered_json& f : info["frames"])
        std::printf("  %6d %10.4g %10llu %10.4g %10.4g %10llu %10.4g\n", f["frame"].get<int>(),
                    f["density"]["max"].get<double>(),
                    static_cast<unsigned long long>(f["density"]["active_voxels"].get<uint64_t>()),
                    f["temperature"]["min"].get<double>(), f["temperature"]["max"].get<double>(),
                    static_cast<unsigned long long>(f["temperature"]["active_voxels"].get<uint64_t>()),
                    f["voxel_size"].get<double>());
    // What loading changed (also warned on stderr), one line per frame and grid that needed it.
    for (const ordered_json& f : info["frames"])
        if (f.contains("cleaned"))
            for (const ordered_json& line : f["cleaned"]["report"])
                std::printf("  frame %d: %s\n", f["frame"].get<int>(), line.get<std::string>().c_str());
}

// info --check: every section's bytes against its checksum (and a compressed one's decoded length),
// then every frame decoded as the runtime decodes it. Throws naming the file and what failed; prints
// what it checked.
void checkPackage(const std::filesystem::path& path) {
    const package::ContainerReader reader = package::ContainerReader::open(path);
    package::SectionBuffer buffer;
    for (const package::SectionInfo& s : reader.sections()) reader.read(s, buffer);  // throws PackageError
    const basis::BasisReader basis = basis::BasisReader::open(path);
    const std::vector<basis::FrameRecord>& frames = basis.description().frames;
    for (const basis::FrameRecord& f : frames) {
        try {
            basis.loadResidentFrame(f.frame, std::pmr::get_default_resource());
            basis.loadFireLights(f.frame);
            basis.loadFireProbes(f.frame);
        } catch (const std::exception& e) {  // any failure to decode is damage to report
            throw Error(ErrorCode::Corrupt, path.string() + ": frame " + std::to_string(f.frame) +
                                                " does not decode: " + e.what());
        }
    }
    std::fprintf(stderr, "firelook: check: %zu sections match their checksums, %zu frames decode\n",
                 reader.sections().size(), frames.size());
}

}  // namespace

void registerInfoCommand(CLI::App& app) {
    auto path = std::make_shared<std::string>();
    auto json = std::make_shared<bool>(false);
    auto flags = std::make_shared<SequenceFlags>();
    CLI::App* cmd = app.add_subcommand("info", "Describe a .firelook package or a VDB sequence");
    cmd->add_option("PATH", *path, "package file, folder of .vdb files, or a pattern such as fire_####.vdb")
        ->required();
    cmd->add_flag("--json", *json, "print JSON on stdout");
    auto check = std::make_shared<bool>(false);
    cmd->add_flag("--check", *check,
                  "a package: also verify every section's checksum and decode every frame; exit 1 naming the "
                  "first fault");
    addSequenceFlags(*cmd, *flags);
    cmd->callback([path, json, flags, check] {
        const bool is_package = looksLikePackage(*path);
        if (*check && !is_package)
            throw Error(ErrorCode::InvalidArgument, *path + ": --check takes a package, not a VDB sequence");
        if (*check) checkPackage(*path);
        const ordered_json info = is_package ? packageInfo(*path) : sequenceInfo(*path, *flags);
        if (*json)
            std::printf("%s\n", info.dump(2).c_str());
        else if (is_package)
            printPackage(info);
        else
            printSequence(info);
    });
}

}  // namespace firelook::cli
