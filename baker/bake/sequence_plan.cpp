#include "bake/sequence_plan.h"

#define XXH_INLINE_ALL
#include <xxhash.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "bake/scene_setup.h"
#include "common/error.h"
#include "reference/frame_medium.h"

namespace firelook::bake {
namespace {

using nlohmann::ordered_json;

constexpr int kPlanVersion = 1;

std::string hex16(XXH64_hash_t hash) {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
    return text;
}

// Adds one loaded frame to the survey.
void surveyFrame(const vdb::VolumeFrame& frame, SequenceSurvey& survey, TemperatureSpan& span,
                 LoadedFrame* keep = nullptr) {
    span.add(frame);
    LoadedFrame loaded = loadFrame(frame);
    survey.temperatures.merge(densityTemperatureRange(loaded.medium));
    survey.density.merge(densityDepth(loaded.medium));
    if (keep) *keep = std::move(loaded);
}

ordered_json vec3Json(const glm::dvec3& v) { return ordered_json::array({v.x, v.y, v.z}); }
glm::dvec3 vec3From(const ordered_json& j) {
    return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()};
}

}  // namespace

const PlannedFrame* SequencePlan::find(int number) const {
    const auto it =
        std::find_if(frames.begin(), frames.end(), [&](const PlannedFrame& f) { return f.number == number; });
    return it == frames.end() ? nullptr : &*it;
}

std::string xxh3Hex(const std::string& text) { return hex16(XXH3_64bits(text.data(), text.size())); }

std::string fileXxh3(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw Error(ErrorCode::IoError, file.string() + ": cannot be read to hash it");
    XXH3_state_t* state = XXH3_createState();
    XXH3_64bits_reset(state);
    std::vector<char> buffer(1 << 20);
    while (in) {
        in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
        XXH3_64bits_update(state, buffer.data(), static_cast<size_t>(in.gcount()));
    }
    const bool failed = in.bad();
    const XXH64_hash_t hash = XXH3_64bits_digest(state);
    XXH3_freeState(state);
    if (failed) throw Error(ErrorCode::IoError, file.string() + ": read error while hashing it");
    return hex16(hash);
}

SequenceSurvey surveySequence(const vdb::VdbSequence& sequence,
                              const std::function<bool(int frame)>& keep_going) {
    SequenceSurvey survey;
    TemperatureSpan span;
    for (const vdb::FrameFile& f : sequence.frames()) {
        if (keep_going && !keep_going(f.number)) throw Error(ErrorCode::Cancelled, "cancelled");
        surveyFrame(sequence.load(f.number), survey, span);
    }
    survey.temperature_range = span.range();
    return survey;
}

LoadedFrame loadFrame(const vdb::VolumeFrame& frame) {
    LoadedFrame loaded;
    loaded.number = frame.number;
    loaded.file = frame.file.filename().string();
    loaded.cleaned_non_finite = frame.cleaned_non_finite;
    loaded.cleaned_negative_density = frame.cleaned_negative_density;
    loaded.clamped_extreme = frame.density_cleaned.clamped + frame.temperature_cleaned.clamped;
    loaded.active_voxels = frame.density_stats.active_voxels;
    loaded.medium = reference::mediumFromFrame(frame);
    return loaded;
}

SequencePlan planSequence(const vdb::VdbSequence& sequence,
                          const std::function<bool(int frame)>& keep_going, int keep, LoadedFrame* kept) {
    SequencePlan plan;
    plan.read = sequence.options();
    plan.world_bounds = sequence.sequenceWorldBounds();
    TemperatureSpan span;
    std::string identity;
    for (const vdb::FrameFile& f : sequence.frames()) {
        if (keep_going && !keep_going(f.number)) throw Error(ErrorCode::Cancelled, "cancelled");
        plan.frames.push_back({f.number, f.path.filename().string(), fileXxh3(f.path)});
        identity += std::to_string(f.number) + " " + plan.frames.back().xxh3_64 + "\n";
        surveyFrame(sequence.load(f.number), plan.survey, span, kept && f.number == keep ? kept : nullptr);
    }
    plan.survey.temperature_range = span.range();
    plan.sequence_xxh3_64 = xxh3Hex(identity);
    return plan;
}

std::string planToJson(const SequencePlan& plan, const std::string& sequence_path) {
    ordered_json frames = ordered_json::array();
    for (const PlannedFrame& f : plan.frames)
        frames.push_back({{"frame", f.number}, {"file", f.file}, {"xxh3_64", f.xxh3_64}});
    const SequenceSurvey& s = plan.survey;
    ordered_json doc = {
        {"firelook_plan", kPlanVersion},
        {"sequence", sequence_path},
        {"sequence_xxh3_64", plan.sequence_xxh3_64},
        {"read",
         {{"density_grid", plan.read.density_grid},
          {"temperature_grid", plan.read.temperature_grid},
          {"temperature_scale", plan.read.temperature_scale},
          {"temperature_offset", plan.read.temperature_offset},
          {"density_scale", plan.read.density_scale},
          {"clamp_extreme", plan.read.clamp_extreme}}},
        // null when no frame has density (JSON has no infinity)
        {"world_bounds", plan.world_bounds.empty() ? ordered_json(nullptr)
                                                   : ordered_json{{"min", vec3Json(plan.world_bounds.min)},
                                                                  {"max", vec3Json(plan.world_bounds.max)}}},
        {"temperature_range", {s.temperature_range.first, s.temperature_range.second}},
        {"temperatures",
         {{"any_density", s.temperatures.any_density},
          {"t_min", s.temperatures.t_min},
          {"t_max", s.temperatures.t_max}}},
        {"density",
         {{"any_density", s.density.any_density},
          {"depth", s.density.depth},
          {"density_p99", s.density.density_p99},
          {"dense_side", s.density.dense_side}}},
        {"frames", frames}};
    return doc.dump(2) + "\n";  // nlohmann writes doubles with 17 significant digits: exact
}

SequencePlan planFromJson(const std::string& text, const std::filesystem::path& file) {
    const ordered_json doc = ordered_json::parse(text, nullptr, false);
    if (doc.is_discarded() || !doc.is_object() || !doc.contains("firelook_plan"))
        throw Error(ErrorCode::Corrupt, file.string() + ": not a plan written by firelook bake --plan-only");
    if (doc.at("firelook_plan") != kPlanVersion)
        throw Error(ErrorCode::Corrupt, file.string() + ": plan version " + doc.at("firelook_plan").dump() +
                                            ", this firelook reads version " + std::to_string(kPlanVersion) +
                                            "; make it again with bake --plan-only");
    SequencePlan plan;
    try {
        plan.sequence_xxh3_64 = doc.at("sequence_xxh3_64").get<std::string>();
        const ordered_json& r = doc.at("read");
        plan.read.density_grid = r.at("density_grid").get<std::string>();
        plan.read.temperature_grid = r.at("temperature_grid").get<std::string>();
        plan.read.temperature_scale = r.at("temperature_scale").get<double>();
        plan.read.temperature_offset = r.at("temperature_offset").get<double>();
        plan.read.density_scale = r.at("density_scale").get<double>();
        plan.read.clamp_extreme = r.at("clamp_extreme").get<bool>();
        if (const ordered_json& b = doc.at("world_bounds"); !b.is_null()) {
            plan.world_bounds.min = vec3From(b.at("min"));
            plan.world_bounds.max = vec3From(b.at("max"));
        }
        SequenceSurvey& s = plan.survey;
        s.temperature_range = {doc.at("temperature_range").at(0).get<double>(),
                               doc.at("temperature_range").at(1).get<double>()};
        const ordered_json& t = doc.at("temperatures");
        s.temperatures.any_density = t.at("any_density").get<bool>();
        s.temperatures.t_min = t.at("t_min").get<double>();
        s.temperatures.t_max = t.at("t_max").get<double>();
        const ordered_json& d = doc.at("density");
        s.density.any_density = d.at("any_density").get<bool>();
        s.density.depth = d.at("depth").get<double>();
        s.density.density_p99 = d.at("density_p99").get<double>();
        s.density.dense_side = d.at("dense_side").get<double>();
        for (const ordered_json& f : doc.at("frames"))
            plan.frames.push_back({f.at("frame").get<int>(), f.at("file").get<std::string>(),
                                   f.at("xxh3_64").get<std::string>()});
    } catch (const nlohmann::json::exception& e) {
        throw Error(ErrorCode::Corrupt, file.string() + ": not a complete plan (" + e.what() + ")");
    }
    if (plan.frames.empty()) throw Error(ErrorCode::Corrupt, file.string() + ": the plan lists no frame");
    return plan;
}

vdb::ReadOptions plannedReadOptions(const SequencePlan& plan, vdb::ReadOptions requested,
                                    const std::filesystem::path& plan_file) {
    const auto differs = [&](const std::string& what, const std::string& planned, const std::string& asked) {
        return Error(ErrorCode::InvalidArgument, plan_file.string() + ": made with " + what + " " + planned +
                                                     ", this bake reads " + asked +
                                                     "; make the plan with the bake's settings");
    };
    const auto text = [](double v) { return ordered_json(v).dump(); };
    if (!requested.density_grid.empty() && requested.density_grid != plan.read.density_grid)
        throw differs("density grid", plan.read.density_grid, requested.density_grid);
    if (!requested.temperature_grid.empty() && requested.temperature_grid != plan.read.temperature_grid)
        throw differs("temperature grid", plan.read.temperature_grid, requested.temperature_grid);
    if (requested.temperature_scale != plan.read.temperature_scale)
        throw differs("temperature_scale", text(plan.read.temperature_scale),
                      text(requested.temperature_scale));
    if (requested.temperature_offset != plan.read.temperature_offset)
        throw differs("temperature_offset", text(plan.read.temperature_offset),
                      text(requested.temperature_offset));
    if (requested.density_scale != plan.read.density_scale)
        throw differs("density_scale", text(plan.read.density_scale), text(requested.density_scale));
    if (requested.clamp_extreme != plan.read.clamp_extreme)
        throw differs("clamp_extreme", plan.read.clamp_extreme ? "on" : "off",
                      requested.clamp_extreme ? "on" : "off");
    requested.density_grid = plan.read.density_grid;
    requested.temperature_grid = plan.read.temperature_grid;
    return requested;
}

void checkPlanFiles(const SequencePlan& plan, const vdb::VdbSequence& sequence,
                    const std::filesystem::path& plan_file) {
    for (const vdb::FrameFile& f : sequence.frames()) {
        const PlannedFrame* planned = plan.find(f.number);
        if (!planned || planned->file != f.path.filename().string())
            throw Error(ErrorCode::InvalidArgument,
                        plan_file.string() + ": " + f.path.string() + " is not in the plan (" +
                            (planned ? "it names frame " + std::to_string(f.number) + " " + planned->file
                                     : "no frame " + std::to_string(f.number)) +
                            "): the plan was made from another sequence or before frames changed");
    }
    if (plan.frames.size() != sequence.frames().size())
        for (const PlannedFrame& p : plan.frames)
            if (!sequence.hasFrame(p.number))
                throw Error(ErrorCode::InvalidArgument,
                            plan_file.string() + ": its frame " + std::to_string(p.number) + " (" + p.file +
                                ") is not in " + sequence.source() +
                                ": the plan was made from another sequence or before frames changed");
}

}  // namespace firelook::bake
