#include "ui_panels.h"

#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>

#include "look_resolution.h"
#include "match_target_panel.h"
#include "ui_image.h"

namespace firelook::viewer {
namespace {

constexpr float kPanelWidth = 420.0f;

bool sliderDouble(const char* label, double& value, double lo, double hi, const char* format = "%.3f") {
    if (!(hi > lo)) {
        ImGui::Text("%s: %.3f (fixed by the bake)", label, value);
        return false;
    }
    return ImGui::SliderScalar(label, ImGuiDataType_Double, &value, &lo, &hi, format);
}

// Colour (max channel 1) and intensity for one emissivity or irradiance.
bool colourIntensity(const char* id, Rgb3& value) {
    ColourIntensity c = splitEmissivity(value);
    ImGui::PushID(id);
    bool changed = ImGui::ColorEdit3("##colour", c.colour.data(), ImGuiColorEditFlags_NoInputs);
    ImGui::SameLine();
    ImGui::SetNextItemWidth(110.0f);
    changed |= ImGui::DragFloat("##intensity", &c.intensity, 0.02f, 0.0f, 1000.0f, "x %.3f");
    ImGui::PopID();
    if (changed) value = joinEmissivity(c);
    return changed;
}

void packagePanel(ViewerApp& app, UiState& ui) {
    // A path field stands in for a file dialog (Dear ImGui has none built in).
    ImGui::InputText("##package", &ui.package_path);
    ImGui::SameLine();
    if (ImGui::Button("Open")) app.openPackage(ui.package_path);
    FireSession* s = app.session();
    if (!s) {
        ImGui::TextWrapped("Type the path of a .firelook package and press Open.");
        return;
    }
    const fl_package_info& i = s->info();
    ImGui::TextWrapped("%s", s->path().c_str());
    ImGui::Text("%dx%d, %d frames (%d-%d), max rank %d", i.width, i.height, i.frame_count, i.first_frame,
                i.last_frame, i.max_rank);
    ImGui::Text("%d bins over T %.3g-%.3g, %d light(s), albedo %.3g", i.bin_count, i.temperature_lo,
                i.temperature_hi, i.light_count, i.albedo);
}

void playbackPanel(ViewerApp& app, FireSession& s) {
    if (ImGui::Button(s.playing() ? "Pause" : "Play")) {
        try {
            s.setPlaying(!s.playing());
        } catch (const std::exception& e) {
            app.setStatus(e.what(), true);
        }
    }
    ImGui::SameLine();
    double fps = s.rate();
    ImGui::SetNextItemWidth(120.0f);
    const double fps_lo = 1.0, fps_hi = 60.0;
    if (ImGui::SliderScalar("fps", ImGuiDataType_Double, &fps, &fps_lo, &fps_hi, "%.0f")) {
        try {
            s.setRate(fps);
        } catch (const std::exception& e) {
            app.setStatus(e.what(), true);
        }
    }
    // Scrub over the baked frames (an index slider that shows frame numbers).
    const std::vector<int>& frames = s.frames();
    const fl_instance_state& state = s.state();
    int index = static_cast<int>(std::find(frames.begin(), frames.end(), state.frame) - frames.begin());
    index = std::clamp(index, 0, static_cast<int>(frames.size()) - 1);
    char label[64];
    std::snprintf(label, sizeof label, "frame %d (rank %d)", frames[index], s.ranks()[index]);
    if (ImGui::SliderInt("##frame", &index, 0, static_cast<int>(frames.size()) - 1, label)) {
        if (s.playing()) s.setPlaying(false);
        app.seekFrame(frames[index]);
    }
    ImGui::Text("position %.2f", state.frame_position);
}

// Switching the emission form keeps the look: bins and stops are made from the resolved emissivity.
void emissionModeSwitch(ViewerApp& app, FireSession& s, LookEdit& look, EmissionMode mode) {
    if (mode == look.mode) return;
    try {
        const fl_package_info& info = s.info();
        if (mode == EmissionMode::Preset) {
            look.preset = presetNames().front();
            look.preset_scale = 1.0;
        } else {
            const std::vector<Rgb3> bins = resolveBins(look, s.package());
            if (mode == EmissionMode::Bins) {
                look.bins = bins;
            } else {
                look.stops.clear();
                for (int b = 0; b < info.bin_count; ++b) look.stops.push_back({binCentre(info, b), bins[static_cast<size_t>(b)]});
            }
        }
        look.mode = mode;
    } catch (const std::exception& e) {
        app.setStatus(e.what(), true);
    }
}

bool emissionEditor(ViewerApp& app, FireSession& s, LookEdit& look) {
    bool changed = false;
    int mode = static_cast<int>(look.mode);
    ImGui::Text("Emission");
    ImGui::SameLine();
    ImGui::RadioButton("preset", &mode, 0);
    ImGui::SameLine();
    ImGui::RadioButton("stops", &mode, 1);
    ImGui::SameLine();
    ImGui::RadioButton("per bin", &mode, 2);
    if (mode != static_cast<int>(look.mode)) {
        emissionModeSwitch(app, s, look, static_cast<EmissionMode>(mode));
        changed = true;
    }
    const fl_package_info& info = s.info();
    switch (look.mode) {
        case EmissionMode::Preset: {
            if (ImGui::BeginCombo("ramp", look.preset.c_str())) {
                for (const std::string& name : presetNames())
                    if (ImGui::Selectable(name.c_str(), name == look.preset)) {
                        look.preset = name;
                        changed = true;
                    }
                ImGui::EndCombo();
            }
            const double lo = 0.0, hi = 50.0;
            changed |= ImGui::SliderScalar("scale", ImGuiDataType_Double, &look.preset_scale, &lo, &hi, "%.3f");
            break;
        }
        case EmissionMode::Stops: {
            // Colour stops: linear between stops, clamped outside, evaluated at the bin centres.
            for (size_t i = 0; i < look.stops.size(); ++i) {
                ImGui::PushID(static_cast<int>(i));
                EmissionStop& stop = look.stops[i];
                // Temperatures stay sorted: each stop moves between its neighbours.
                const double lo = i > 0 ? look.stops[i - 1].temperature : info.temperature_lo;
                const double hi = i + 1 < look.stops.size() ? look.stops[i + 1].temperature : info.temperature_hi;
                ImGui::SetNextItemWidth(110.0f);
                changed |= ImGui::DragScalar("##T", ImGuiDataType_Double, &stop.temperature, 0.005f, &lo, &hi, "T %.3f",
                                             ImGuiSliderFlags_AlwaysClamp);
                ImGui::SameLine();
                changed |= colourIntensity("e", stop.emissivity);
                ImGui::SameLine();
                if (ImGui::SmallButton("x") && look.stops.size() > 1) {
                    look.stops.erase(look.stops.begin() + static_cast<long>(i));
                    changed = true;
                    ImGui::PopID();
                    break;
                }
                ImGui::PopID();
            }
            if (ImGui::SmallButton("+ stop")) {
                EmissionStop stop = look.stops.empty() ? EmissionStop{info.temperature_hi, {1, 1, 1}} : look.stops.back();
                stop.temperature = std::max(stop.temperature, info.temperature_hi);
                look.stops.push_back(stop);
                changed = true;
            }
            break;
        }
        case EmissionMode::Bins:
            for (size_t b = 0; b < look.bins.size(); ++b) {
                char id[48];
                std::snprintf(id, sizeof id, "bin%zu", b);
                ImGui::Text("%2zu  T %6.3f", b, binCentre(info, static_cast<int>(b)));
                ImGui::SameLine();
                changed |= colourIntensity(id, look.bins[b]);
            }
            break;
    }
    return changed;
}

// The run-time light (fl_instance_set_light_direction): two angles in the camera's frame and its
// irradiance; it takes the place of the six-way or sphere lights' irradiance of the look.
void lightDirectionControl(ViewerApp& app, FireSession& s) {
    LightDirection light = s.lightDirection();
    bool changed = ImGui::Checkbox("light from a direction (six-way or sphere lights)", &light.enabled);
    changed |= ImGui::SliderFloat("azimuth", &light.azimuth_degrees, -180.0f, 180.0f, "%.0f deg");
    changed |= ImGui::SliderFloat("elevation", &light.elevation_degrees, -90.0f, 90.0f, "%.0f deg");
    ImGui::Text("irradiance");
    ImGui::SameLine();
    changed |= colourIntensity("direction light", light.irradiance);
    if (changed) app.editLightDirection(light);
}

void lookPanel(ViewerApp& app, UiState& ui, FireSession& s) {
    const fl_package_info& info = s.info();
    // Presets: the package's default look and the look files of samples/looks.
    if (ImGui::BeginCombo("preset", "choose a look...")) {
        if (ImGui::Selectable("package default")) app.applyPreset({"package default", s.defaultLookJson()});
        for (const LookPreset& p : app.presets())
            if (ImGui::Selectable(p.name.c_str())) app.applyPreset(p);
        ImGui::EndCombo();
    }
    const bool keyed = s.animateKeys() && !s.keys().empty();
    if (keyed) {
        const fl_instance_state& st = s.state();
        ImGui::TextColored(ImVec4(1.0f, 0.8f, 0.3f, 1.0f), "Keyframes playing: T_c %.3f, k_s %.3f, k_f %.3f",
                           st.temperature_threshold, st.smoke_extinction, st.flame_extinction);
        ImGui::TextWrapped("Edits below change the look that 'Set key' stores; untick 'Play keyframes' to see them.");
    }
    LookEdit look = s.look();
    bool changed = false;
    changed |= sliderDouble("T_c", look.temperature_threshold, info.temperature_threshold_min,
                            info.temperature_threshold_max);
    changed |= sliderDouble("k_s", look.smoke_extinction, info.smoke_extinction_min, info.smoke_extinction_max);
    changed |= sliderDouble("k_f", look.flame_extinction, info.flame_extinction_min, info.flame_extinction_max);
    ImGui::Text("albedo %.3f (fixed by the bake)", look.albedo);
    changed |= emissionEditor(app, s, look);
    // A sphere's lights (12 or 42) are set through the light-direction control, not one by one.
    const bool sphere = s.hasRelightLights() && s.relightLightCount() > 6;
    for (size_t l = 0; l < look.lights.size(); ++l) {
        if (sphere && static_cast<int>(l) == s.relightFirstLight())
            ImGui::TextWrapped("lights %d-%d: the sphere's %d, lit by the light from a direction below",
                               s.relightFirstLight(), s.relightFirstLight() + s.relightLightCount() - 1,
                               s.relightLightCount());
        if (sphere && static_cast<int>(l) >= s.relightFirstLight()) continue;
        char id[32];
        std::snprintf(id, sizeof id, "light %zu", l);
        ImGui::Text("%s", id);
        ImGui::SameLine();
        changed |= colourIntensity(id, look.lights[l]);
    }
    if (changed) app.editLook(look);
    if (s.hasRelightLights()) lightDirectionControl(app, s);

    ImGui::InputText("##lookpath", &ui.look_path);
    ImGui::SameLine();
    if (ImGui::Button("Load##look")) app.loadLookFile(ui.look_path);
    ImGui::SameLine();
    if (ImGui::Button("Save##look")) app.saveLookFile(ui.look_path);
}

void keyframesPanel(ViewerApp& app, UiState& ui, FireSession& s) {
    char label[64];
    std::snprintf(label, sizeof label, "Set key at frame %d", s.state().frame);
    if (ImGui::Button(label)) app.setKeyAtCurrentFrame();
    ImGui::SameLine();
    bool animate = s.animateKeys();
    if (ImGui::Checkbox("Play keyframes", &animate)) app.setAnimateKeys(animate);
    std::vector<Keyframe>& keys = s.keys();
    for (size_t i = 0; i < keys.size(); ++i) {
        ImGui::PushID(static_cast<int>(i));
        ImGui::Text("frame %g  T_c %.2f k_s %.2f k_f %.2f", keys[i].frame, keys[i].look.temperature_threshold,
                    keys[i].look.smoke_extinction, keys[i].look.flame_extinction);
        ImGui::SameLine();
        if (ImGui::SmallButton("go")) app.seekFrame(keys[i].frame);
        ImGui::SameLine();
        if (ImGui::SmallButton("edit")) app.editLook(keys[i].look);
        ImGui::SameLine();
        if (ImGui::SmallButton("delete")) {
            app.deleteKey(i);
            ImGui::PopID();
            break;
        }
        ImGui::PopID();
    }
    ImGui::InputText("##keypath", &ui.keyframes_path);
    ImGui::SameLine();
    if (ImGui::Button("Load##keys")) app.loadKeyframesFile(ui.keyframes_path);
    ImGui::SameLine();
    if (ImGui::Button("Save##keys")) app.saveKeyframesFile(ui.keyframes_path);
}

void displayPanel(ViewerApp& app) {
    int path = app.path == ReconstructionPath::Gpu ? 0 : 1;
    ImGui::Text("Reconstruction");
    ImGui::SameLine();
    if (!app.gpuAvailable()) ImGui::BeginDisabled();
    ImGui::RadioButton("GPU", &path, 0);
    if (!app.gpuAvailable()) {
        ImGui::EndDisabled();
        if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) ImGui::SetTooltip("%s", app.gpuError().c_str());
    }
    ImGui::SameLine();
    ImGui::RadioButton("CPU", &path, 1);
    app.path = path == 0 ? ReconstructionPath::Gpu : ReconstructionPath::Cpu;
    if (!app.gpuAvailable()) ImGui::BeginDisabled();
    ImGui::Checkbox("difference GPU vs CPU", &app.compare);
    if (!app.gpuAvailable()) ImGui::EndDisabled();
    if (app.compare && app.gpuAvailable()) {
        ImGui::SliderFloat("gain (stops)", &app.difference_gain_stops, 0.0f, 30.0f, "%.0f");
        const PathDifference& d = app.pathDifference();
        ImGui::Text("max |GPU - CPU|: RGB %.3g (%.3g of the peak)", d.max_rgb, d.max_rgb_relative);
        ImGui::Text("                 alpha %.3g", d.max_alpha);
    }
    ImGui::SliderFloat("exposure", &app.display.exposure_stops, -10.0f, 10.0f, "%.2f stops");
    int bg = app.display.checker ? 0 : 1;
    ImGui::Text("Background");
    ImGui::SameLine();
    ImGui::RadioButton("checker", &bg, 0);
    ImGui::SameLine();
    ImGui::RadioButton("solid", &bg, 1);
    app.display.checker = bg == 0;
    if (!app.display.checker) {
        ImGui::SameLine();
        ImGui::ColorEdit3("##bg", app.display.solid.data(), ImGuiColorEditFlags_NoInputs | ImGuiColorEditFlags_Float);
    }
    FlareSettings& f = app.flare;
    ImGui::Checkbox("lens flare", &f.enabled);
    if (f.enabled && ImGui::TreeNode("flare settings")) {
        ImGui::SliderFloat("threshold", &f.threshold, 0.0f, 20.0f, "%.3f");
        ImGui::SliderFloat("intensity", &f.intensity, 0.0f, 2.0f, "%.3f");
        ImGui::SliderInt("ghosts", &f.ghost_count, 0, 8);
        ImGui::SliderFloat("ghost spacing", &f.ghost_spacing, 0.05f, 1.5f, "%.3f");
        ImGui::SliderFloat("halo radius", &f.halo_radius, 0.05f, 1.5f, "%.3f");
        ImGui::SliderFloat("halo width", &f.halo_width, 0.01f, 0.5f, "%.3f");
        ImGui::SliderFloat("halo intensity", &f.halo_intensity, 0.0f, 2.0f, "%.3f");
        ImGui::SliderFloat("streak length", &f.streak_length, 0.005f, 0.5f, "%.3f");
        ImGui::SliderFloat("streak intensity", &f.streak_intensity, 0.0f, 2.0f, "%.3f");
        ImGui::SliderInt("streaks (1 h, 2 h+v)", &f.streaks, 0, 2);
        ImGui::TreePop();
    }
}

void qaPanel(ViewerApp& app) {
    ReferenceRequest& q = app.qa_settings;
    ImGui::InputTextWithHint("sequence", "recorded in the package", &q.sequence_override);
    ImGui::SliderInt("spp per pass", &q.spp_per_pass, 1, 64);
    ImGui::SliderInt("target spp", &q.target_spp, 4, 4096, "%d", ImGuiSliderFlags_Logarithmic);
    const ReferenceSnapshot& r = app.qa();
    if (ImGui::Button("Render reference")) app.startQa();
    ImGui::SameLine();
    if (ImGui::Button("Stop")) app.stopQa();
    if (!app.qaStarted()) return;
    ImGui::TextWrapped("%s", r.status.c_str());
    if (!r.error.empty()) ImGui::TextColored(ImVec4(1, 0.35f, 0.3f, 1), "%s", r.error.c_str());
    if (r.target_spp > 0)
        ImGui::ProgressBar(static_cast<float>(r.spp) / static_cast<float>(r.target_spp), ImVec2(-1, 0));
    if (r.spp > 0) {
        const ErrorMeasures& m = app.qaMeasures();
        ImGui::Text("relative RMSE %.4f   max alpha error %.4f", m.relative_rmse, m.max_alpha_error);
        ImGui::Text("reference noise (estimated) %.4f, %.1f s", r.estimated_relative_rmse, r.seconds);
        ImGui::SliderFloat("heat map white at", &app.heat_scale, 0.01f, 2.0f, "%.2f x RMS", ImGuiSliderFlags_Logarithmic);
    }
    if (!app.qaCompareError().empty()) ImGui::TextColored(ImVec4(1, 0.35f, 0.3f, 1), "%s", app.qaCompareError().c_str());
    if (app.qaStale())
        ImGui::TextColored(ImVec4(1, 0.8f, 0.3f, 1), "frame or look changed since the reference started");
}

void exportPanel(ViewerApp& app, UiState& ui) {
    ImGui::Checkbox("32-bit float EXR", &app.export_options.float_exr);
    ImGui::SameLine();
    ImGui::Checkbox("PNG over solid bg", &app.export_png_over_background);
    ImGui::Checkbox("include lens flare", &app.export_include_flare);
    ImGui::InputText("##exportfile", &ui.export_path);
    ImGui::SameLine();
    if (ImGui::Button("Export frame")) app.exportCurrent(ui.export_path);
    ImGui::InputText("##exportpattern", &ui.export_pattern);
    ImGui::SameLine();
    if (app.exporting()) {
        ImGui::ProgressBar(app.exportProgress(), ImVec2(-1, 0));
    } else if (ImGui::Button("Export sequence")) {
        app.startSequenceExport(ui.export_pattern);
    }
}

void timingsPanel(ViewerApp& app) {
    const StageTimes last = app.timings().last(), median = app.timings().median();
    ImGui::Text("path %s", app.compare && app.gpuAvailable() ? "GPU + CPU (difference)" : app.usingGpu() ? "GPU" : "CPU");
    if (ImGui::BeginTable("timings", 3, ImGuiTableFlags_SizingFixedFit)) {
        ImGui::TableSetupColumn("stage (ms)");
        ImGui::TableSetupColumn("last");
        ImGui::TableSetupColumn("median");
        ImGui::TableHeadersRow();
        const auto row = [](const char* name, double a, double b) {
            ImGui::TableNextRow();
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(name);
            ImGui::TableNextColumn();
            ImGui::Text("%8.2f", a);
            ImGui::TableNextColumn();
            ImGui::Text("%8.2f", b);
        };
        row("update", last.update_ms, median.update_ms);
        row("upload", last.upload_ms, median.upload_ms);
        row("draw", last.draw_ms, median.draw_ms);
        row("frame", last.frame_ms, median.frame_ms);
        ImGui::EndTable();
    }
    ImGui::Text("%.1f fps (median frame)", median.frame_ms > 0 ? 1000.0 / median.frame_ms : 0.0);
}

void viewport(ViewerApp& app, const FireLightView& fire_lights, const FireProbeView& fire_probes, float x,
              float width, float height) {
    ImGui::SetNextWindowPos(ImVec2(x, 0));
    ImGui::SetNextWindowSize(ImVec2(width, height));
    ImGui::Begin("Image", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
    FireSession* s = app.session();
    if (s && app.displayTarget().texture()) {
        const float aspect = static_cast<float>(s->info().height) / static_cast<float>(s->info().width);
        const ImVec2 avail = ImGui::GetContentRegionAvail();
        const float caption = ImGui::GetTextLineHeightWithSpacing();
        const bool qa = app.qaStarted() && app.qaReferenceTexture();
        if (matchTargetImages(app, avail.x, aspect)) {
            // The fit's row replaces the real-time image while it is shown (Match target panel).
        } else if (!qa) {
            const float w = std::min(avail.x, (avail.y - caption) / aspect);
            const char* what = app.compare && app.gpuAvailable() ? "|GPU - CPU| x gain" : app.usingGpu() ? "real time (GPU)" : "real time (CPU)";
            imageWithCaption(what, app.displayTarget().texture(), w, aspect);
            // The group's rectangle holds the caption above the image: the image is its bottom w x w*aspect.
            const ImVec2 low(ImGui::GetItemRectMin().x, ImGui::GetItemRectMax().y - w * aspect);
            drawFireProbeDots(*s, fire_probes, low, ImVec2(low.x + w, low.y + w * aspect));
            drawFireLightMarkers(*s, fire_lights, low, ImVec2(low.x + w, low.y + w * aspect));
        } else {
            // 2 x 2: real time now | reference; the real-time image the QA compares (taken when the
            // reference started) | the error heat map.
            const float spacing = ImGui::GetStyle().ItemSpacing.x;
            const float w = std::min((avail.x - spacing) / 2.0f, (avail.y - 2 * caption - spacing) / (2.0f * aspect));
            imageWithCaption("real time (now)", app.displayTarget().texture(), w, aspect);
            ImGui::SameLine();
            imageWithCaption("reference (path traced)", app.qaReferenceTexture(), w, aspect);
            imageWithCaption("real time (compared)", app.qaRealtimeTexture(), w, aspect);
            ImGui::SameLine();
            imageWithCaption("error heat map", app.qaHeatTexture(), w, aspect);
        }
    }
    ImGui::End();
}

}  // namespace

void drawUi(ViewerApp& app, UiState& ui, int window_width, int window_height) {
    const float panel = std::min(kPanelWidth, static_cast<float>(window_width) * 0.5f);
    ImGui::SetNextWindowPos(ImVec2(0, 0));
    ImGui::SetNextWindowSize(ImVec2(panel, static_cast<float>(window_height)));
    ImGui::Begin("FireLook", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
    if (!app.status.text.empty())
        ImGui::TextColored(app.status.error ? ImVec4(1, 0.35f, 0.3f, 1) : ImVec4(0.6f, 0.9f, 0.6f, 1), "%s",
                           app.status.text.c_str());
    if (ImGui::CollapsingHeader("Package", ImGuiTreeNodeFlags_DefaultOpen)) packagePanel(app, ui);
    if (FireSession* s = app.session()) {
        if (ImGui::CollapsingHeader("Playback", ImGuiTreeNodeFlags_DefaultOpen)) playbackPanel(app, *s);
        if (ImGui::CollapsingHeader("Look", ImGuiTreeNodeFlags_DefaultOpen)) lookPanel(app, ui, *s);
        if (ImGui::CollapsingHeader("Keyframes")) keyframesPanel(app, ui, *s);
        if (ImGui::CollapsingHeader("Display", ImGuiTreeNodeFlags_DefaultOpen)) displayPanel(app);
        if (ImGui::CollapsingHeader("Fire lights")) fireLightPanel(*s, ui.fire_lights);
        if (ImGui::CollapsingHeader("Fire probes")) fireProbePanel(*s, ui.fire_probes);
        if (ImGui::CollapsingHeader("QA: reference", ImGuiTreeNodeFlags_DefaultOpen)) qaPanel(app);
        // Opened once a fit has been started (e.g. by --match-target).
        if (app.match().status != FitStatus::Idle) ImGui::SetNextItemOpen(true, ImGuiCond_Once);
        if (ImGui::CollapsingHeader("Match target")) matchTargetPanel(app);
        if (ImGui::CollapsingHeader("Export")) exportPanel(app, ui);
        if (ImGui::CollapsingHeader("Timings", ImGuiTreeNodeFlags_DefaultOpen)) timingsPanel(app);
    }
    ImGui::End();
    viewport(app, ui.fire_lights, ui.fire_probes, panel, static_cast<float>(window_width) - panel,
             static_cast<float>(window_height));
}

}  // namespace firelook::viewer
