#include "match_target_panel.h"

#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>

#include "ui_image.h"

namespace firelook::viewer {
namespace {

const ImVec4 kError(1, 0.35f, 0.3f, 1);

}  // namespace

void matchTargetPanel(ViewerApp& app) {
    FitRequest& r = app.match_request;
    const FitSnapshot& m = app.match();
    const bool running = m.status == FitStatus::Running;
    ImGui::InputTextWithHint("target", ".exr (linear) or .png", &r.target);
    int mask = static_cast<int>(r.mask_kind);
    ImGui::RadioButton("no mask", &mask, static_cast<int>(MaskKind::None));
    ImGui::SameLine();
    ImGui::RadioButton("mask file", &mask, static_cast<int>(MaskKind::File));
    ImGui::SameLine();
    ImGui::RadioButton("threshold", &mask, static_cast<int>(MaskKind::Threshold));
    r.mask_kind = static_cast<MaskKind>(mask);
    if (r.mask_kind == MaskKind::File) ImGui::InputTextWithHint("mask", "weight = red channel", &r.mask);
    if (r.mask_kind == MaskKind::Threshold) {
        ImGui::SliderFloat("above", &r.threshold, 0.0f, 1.0f, "%.4f", ImGuiSliderFlags_Logarithmic);
        ImGui::Checkbox("on alpha (else luminance)", &r.threshold_on_alpha);
    }
    bool over = r.background.has_value();
    if (ImGui::Checkbox("opaque over a background", &over))
        r.background = over ? std::optional<Rgb3>(Rgb3{0.0f, 0.0f, 0.0f}) : std::nullopt;
    if (r.background) ImGui::ColorEdit3("background (linear)", r.background->data(), ImGuiColorEditFlags_Float);
    float exposure = static_cast<float>(r.exposure);
    if (ImGui::SliderFloat("target exposure", &exposure, -8.0f, 8.0f, "%.2f stops")) r.exposure = exposure;
    float smooth = static_cast<float>(r.smoothness);
    if (ImGui::SliderFloat("smoothness", &smooth, 0.0f, 10.0f, "%.3f", ImGuiSliderFlags_Logarithmic))
        r.smoothness = smooth;

    ImGui::BeginDisabled(running);
    if (ImGui::Button("Fit frame shown")) app.startMatch();
    ImGui::EndDisabled();
    ImGui::SameLine();
    ImGui::BeginDisabled(!running);
    if (ImGui::Button("Cancel")) app.cancelMatch();
    ImGui::EndDisabled();
    ImGui::SameLine();
    ImGui::BeginDisabled(m.status != FitStatus::Done);
    if (ImGui::Button("Accept")) app.acceptMatch();
    ImGui::EndDisabled();

    if (running) ImGui::ProgressBar(static_cast<float>(m.fraction), ImVec2(-1, 0));
    if (m.status == FitStatus::Cancelled) ImGui::TextUnformatted("cancelled: the look is unchanged");
    if (m.status == FitStatus::Failed) ImGui::TextColored(kError, "%s", m.error.c_str());
    if (m.status == FitStatus::Done) {
        ImGui::Text("relative RMSE %.3f %%, %.1f s, %d extinction settings", 100.0 * m.report.relative_rmse,
                    m.seconds, m.report.evaluations);
        if (m.report.alpha_max_error > 0.0)
            ImGui::Text("alpha RMSE %.4f, max alpha error %.4f", m.report.alpha_rmse, m.report.alpha_max_error);
        if (m.clipped_pixels > 0) ImGui::Text("%zu clipped target pixels left out", m.clipped_pixels);
        ImGui::Checkbox("show target / fit / difference", &app.match_shown);
    }
}

bool matchTargetImages(ViewerApp& app, float width, float aspect) {
    if (!app.match_shown || app.match().status != FitStatus::Done) return false;
    const float spacing = ImGui::GetStyle().ItemSpacing.x;
    const float w = std::min((width - 2 * spacing) / 3.0f, 512.0f);
    imageWithCaption("target", app.matchTargetTexture(), w, aspect);
    ImGui::SameLine();
    imageWithCaption("fit", app.matchFitTexture(), w, aspect);
    ImGui::SameLine();
    imageWithCaption("|fit - target|", app.matchDifferenceTexture(), w, aspect);
    return true;
}

}  // namespace firelook::viewer
