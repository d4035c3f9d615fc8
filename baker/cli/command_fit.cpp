// firelook fit PACKAGE (--frame F | --frames A-B) --target IMG [--mask IMG] [--background R,G,B]
//              [--fix k_s=V ...] [--smooth L] [--exposure E] -o LOOK.json [--image IMG] [--difference IMG]
// Inverse design (issue 17): the look inside the baked ranges whose recombined image best matches
// a target (runtime/fit/look_fit.h), written as a look file that render, the viewer and the plugin read.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory_resource>
#include <optional>
#include <stdexcept>
#include <utility>

#include "bake/scene_setup.h"
#include "basis/basis_package.h"
#include "cli/commands.h"
#include "cli/interrupt.h"
#include "cli/output_option.h"
#include "cli/progress_bar.h"
#include "common/error.h"
#include "fit/look_fit.h"
#include "image/fit_target.h"
#include "image/image_io.h"
#include "look/look.h"

namespace firelook::cli {
namespace {

// A path whose runs of '#' stand for the frame number, zero-padded to the run's length.
std::string framePath(const std::string& pattern, int frame) {
    const size_t first = pattern.find('#');
    if (first == std::string::npos) return pattern;
    const size_t last = pattern.find_first_not_of('#', first);
    const size_t width = (last == std::string::npos ? pattern.size() : last) - first;
    std::string number = std::to_string(frame);
    if (number.size() < width) number.insert(0, width - number.size(), '0');
    return pattern.substr(0, first) + number + (last == std::string::npos ? "" : pattern.substr(last));
}

Rgb parseBackground(const std::string& text) {
    float r = 0, g = 0, b = 0;
    char extra = 0;
    const int n = std::sscanf(text.c_str(), "%f,%f,%f%c", &r, &g, &b, &extra);
    if (n == 1) g = b = r;
    if ((n != 1 && n != 3) || !(r >= 0 && g >= 0 && b >= 0) || !std::isfinite(r + g + b))
        throw Error(ErrorCode::InvalidArgument,
                    "--background '" + text + "': expected R,G,B (or one value), linear, >= 0");
    return Rgb(r, g, b);
}

void applyFix(const std::string& text, fit::FitOptions& options) {
    const size_t eq = text.find('=');
    const std::string name = text.substr(0, eq);
    double value = 0;
    char extra = 0;
    if (eq == std::string::npos || std::sscanf(text.c_str() + eq + 1, "%lf%c", &value, &extra) != 1)
        throw Error(ErrorCode::InvalidArgument,
                    "--fix '" + text + "': expected NAME=VALUE, NAME one of T_c, k_s, k_f");
    if (name == "T_c" || name == "temperature_threshold") options.temperature_threshold = value;
    else if (name == "k_s" || name == "smoke_extinction") options.smoke_extinction = value;
    else if (name == "k_f" || name == "flame_extinction") options.flame_extinction = value;
    else
        throw Error(ErrorCode::InvalidArgument,
                    "--fix '" + text + "': unknown parameter '" + name + "' (T_c, k_s or k_f)");
}

struct TargetFlags {
    std::string target, mask, background;
    double exposure = 0.0;
};

// One frame's target and mask (image/fit_target.h, shared with the viewer) as the fit takes it;
// adds the clipped pixels it left out to `clipped_pixels`.
fit::FrameTarget readTarget(const TargetFlags& flags, int frame, const basis::BakeDescription& d, size_t& clipped_pixels) {
    image::FitTargetRequest request;
    request.target = framePath(flags.target, frame);
    if (!flags.mask.empty()) request.mask = framePath(flags.mask, frame);
    request.width = d.width;
    request.height = d.height;
    request.frame = frame;
    if (!flags.background.empty()) {
        const Rgb b = parseBackground(flags.background);
        request.background = std::array<float, 3>{b.r, b.g, b.b};
    }
    request.exposure = flags.exposure;
    image::FitTargetImage read = image::readFitTarget(request);
    clipped_pixels += read.clipped_pixels;
    fit::FrameTarget target;
    target.frame = frame;
    target.rgba = std::move(read.rgba);
    target.weight = std::move(read.weight);
    target.match_alpha = read.match_alpha;
    target.background = Rgb(read.background[0], read.background[1], read.background[2]);
    return target;
}

void writeOutputs(const std::string& image_pattern, const std::string& difference_pattern, double exposure,
                  const basis::BakeDescription& d, const std::vector<fit::FrameTarget>& targets,
                  const fit::FitResult& result) {
    image::WriteOptions options;
    options.png_exposure_stops = exposure;
    for (size_t f = 0; f < targets.size(); ++f) {
        const fit::FrameTarget& t = targets[f];
        if (!image_pattern.empty()) {
            image::ImageRGBA out(d.width, d.height);
            out.pixels = result.images[f];
            // The PNG writer composites after the exposure: the background as given, not as fitted.
            if (!t.match_alpha) {
                const Rgb shown = t.background * static_cast<float>(std::exp2(exposure));
                options.png_background = std::array<float, 3>{shown.r, shown.g, shown.b};
            }
            image::writeImage(framePath(image_pattern, t.frame), out, options);
        }
        if (!difference_pattern.empty()) {
            image::ImageRGBA diff(d.width, d.height);
            diff.pixels = image::fitDifference(t.rgba, t.match_alpha, {t.background.r, t.background.g, t.background.b},
                                               result.images[f]);
            image::WriteOptions diff_options;
            diff_options.png_exposure_stops = exposure;
            image::writeImage(framePath(difference_pattern, t.frame), diff, diff_options);
        }
    }
}

}  // namespace

void registerFitCommand(CLI::App& app) {
    struct Args {
        std::string package, out, frames, image, difference;
        std::optional<int> frame;
        TargetFlags target;
        std::vector<std::string> fix;
        fit::FitOptions options;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = app.add_subcommand(
        "fit", "Find the look (T_c, k_s, k_f, per-bin emission, light) whose image best matches a target");
    cmd->add_option("PACKAGE", args->package, ".firelook package")->required()->check(CLI::ExistingFile);
    CLI::Option* frame = cmd->add_option("--frame", args->frame, "frame the target shows");
    CLI::Option* frames = cmd->add_option("--frames", args->frames,
                                          "several frames, A-B ranges and single frames comma-separated: one look "
                                          "for all of them (--target and --mask then need '#' for the frame number)");
    frame->excludes(frames);
    frames->excludes(frame);
    cmd->add_option("--target", args->target.target,
                    "target image: .exr linear premultiplied RGBA (alpha matched unless opaque) or .png (fitted "
                    "through the display transform render uses for PNG); '#'s stand for the frame number")
        ->required();
    cmd->add_option("--mask", args->target.mask, "weight per pixel from the mask's red channel (0 leaves a pixel out)");
    cmd->add_option("--background", args->target.background,
                    "R,G,B (linear) the target was composited over; its alpha is then not matched "
                    "(an opaque target without it: black)");
    cmd->add_option("--fix", args->fix, "hold a parameter: T_c=V, k_s=V or k_f=V (repeatable)");
    cmd->add_option("--smooth", args->options.smoothness,
                    "weight of the emission's second differences across bins (0: each bin free)")
        ->capture_default_str();
    cmd->add_option("--alpha-weight", args->options.alpha_weight, "weight of the alpha error against the colour's")
        ->capture_default_str();
    cmd->add_option("--starts", args->options.starts, "grid points the local search starts from")
        ->capture_default_str()
        ->check(CLI::Range(1, 1000));
    cmd->add_option("--exposure", args->target.exposure,
                    "stops the target (PNG) was exposed by; the look renders it with render --exposure E")
        ->capture_default_str();
    addOutputOption(*cmd, args->out, "look file to write (JSON)")->required();
    cmd->add_option("--image", args->image, "also write the fitted look's image (.exr or .png; '#' = frame)");
    cmd->add_option("--difference", args->difference, "also write |fit - target| (.exr or .png; '#' = frame)");
    cmd->callback([args] {
        if (!args->frame && args->frames.empty())
            throw Error(ErrorCode::InvalidArgument, "fit: give --frame F or --frames A-B");
        if (!std::isfinite(args->target.exposure))
            throw Error(ErrorCode::InvalidArgument, "--exposure must be finite");
        for (const std::string& f : args->fix) applyFix(f, args->options);
        const auto start = std::chrono::steady_clock::now();
        const basis::BasisReader package = basis::BasisReader::open(args->package);
        const basis::BakeDescription& d = package.description();

        std::vector<int> selected;
        if (args->frame) {
            selected.push_back(*args->frame);
        } else {
            for (const auto& [first, last] : bake::parseFrameRanges(args->frames))
                for (int f = first; f <= last; ++f) selected.push_back(f);
        }
        for (int f : selected)
            if (!d.findFrame(f))
                throw Error(ErrorCode::InvalidArgument,
                            args->package + ": has no frame " + std::to_string(f));
        if (selected.size() > 1 && args->target.target.find('#') == std::string::npos)
            throw Error(ErrorCode::InvalidArgument,
                        "--target " + args->target.target +
                            ": several frames need one target each ('#' for the frame number)");

        std::vector<fit::FrameTarget> targets;
        std::vector<basis::ResidentFrame> resident;
        size_t clipped = 0;
        for (int f : selected) {
            targets.push_back(readTarget(args->target, f, d, clipped));
            resident.push_back(package.loadResidentFrame(f, std::pmr::get_default_resource()));
            throwIfInterrupted();
        }
        std::vector<const basis::ResidentFrame*> frame_ptrs;
        for (const basis::ResidentFrame& r : resident) frame_ptrs.push_back(&r);

        const auto fit_start = std::chrono::steady_clock::now();
        ProgressBar bar("fit");
        const fit::FitResult result = fit::fitLook(d, frame_ptrs, targets, args->options, [&](double fraction) {
            throwIfInterrupted();
            bar.update(fraction);
        });
        const double fit_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - fit_start).count();
        throwIfInterrupted();  // before anything is written
        bar.finish();

        writeOutputs(args->image, args->difference, args->target.exposure, d, targets, result);
        saveLook(args->out, result.look);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

        const Look& look = result.look;
        const bool alpha = targets.front().match_alpha;
        std::printf("fit %zu frame(s) of %s to %s: relative RMSE %.4f%% (linear RGB%s)", targets.size(),
                    args->package.c_str(), args->target.target.c_str(), 100.0 * result.relative_rmse,
                    image::isPngPath(args->target.target) ? ", display-weighted fit" : "");
        if (alpha)
            std::printf(", alpha RMSE %.5f, max alpha error %.4f", result.alpha_rmse, result.alpha_max_error);
        std::printf("\n");
        // A clipped pixel says only that its value was at least the clip: it is left out, so a target
        // clipped over its core constrains the hottest bins at the core's edge alone.
        if (clipped > 0)
            std::printf("  %zu clipped target pixels left out (a less exposed target constrains them)\n", clipped);
        if (targets.size() > 1)
            for (const fit::FrameFitError& e : result.frames)
                std::printf("  frame %d: relative RMSE %.4f%%%s\n", e.frame, 100.0 * e.relative_rmse,
                            alpha ? (", max alpha error " + std::to_string(e.alpha_max_error)).c_str() : "");
        std::printf("  T_c %.6g  k_s %.6g  k_f %.6g  (baked T_c [%g, %g], k_s [%g, %g], k_f [%g, %g])\n",
                    look.temperature_threshold, look.smoke_extinction, look.flame_extinction,
                    d.axes.temperature_threshold.front(), d.axes.temperature_threshold.back(),
                    d.axes.smoke_extinction.front(), d.axes.smoke_extinction.back(), d.axes.flame_extinction.front(),
                    d.axes.flame_extinction.back());
        const auto& bins = std::get<EmissionBins>(look.emission).emissivity;
        std::printf("  emissivity at the bin centres (T: r g b):\n");
        for (int i = 0; i < d.bins.count; ++i)
            std::printf("    %.4g: %.5g %.5g %.5g\n", d.bins.center(i), bins[i].r, bins[i].g, bins[i].b);
        for (size_t l = 0; l < look.light_irradiance.size(); ++l)
            std::printf("  light %zu irradiance: %.5g %.5g %.5g\n", l, look.light_irradiance[l].r,
                        look.light_irradiance[l].g, look.light_irradiance[l].b);
        std::printf("  %d extinction settings tried; fit %.3f s, %.3f s in all\n", result.evaluations, fit_seconds,
                    seconds);
        std::printf("wrote %s\n", args->out.c_str());
    });
}

}  // namespace firelook::cli
