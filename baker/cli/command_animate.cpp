// firelook animate PACKAGE --key F:LOOK.json [--key ...] -o DIR
// Renders every frame of a package with a look keyframed across the sequence:
// at each frame the look is blended between the surrounding keys by the runtime's one keyed-look
// rule (runtime/look/look_blend.h, the paper's figure 1), held constant before the first and after
// the last, so each frame shows what the world and the C API show for the same keys.
// Writes DIR/frame_NNNN.png (and .exr with --exr) and DIR/contact_sheet.png: all or nothing
// (cli/staging_folder.h).
#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "basis/basis_package.h"
#include "basis/look_renderer.h"
#include "cli/commands.h"
#include "cli/interrupt.h"
#include "cli/output_option.h"
#include "cli/progress_bar.h"
#include "cli/staging_folder.h"
#include "common/error.h"
#include "image/contact_sheet.h"
#include "image/image_io.h"
#include "look/look_blend.h"
#include "world/keyframe_bracket.h"

namespace firelook::cli {
namespace {

struct LookKey {
    int frame = 0;
    Look look;
};

LookKey parseKey(const std::string& text) {
    const size_t colon = text.find(':');
    if (colon == std::string::npos || colon == 0)
        throw Error(ErrorCode::InvalidArgument, "--key '" + text + "' is not FRAME:LOOK.json");
    LookKey key;
    try {
        key.frame = std::stoi(text.substr(0, colon));
    } catch (const std::exception&) {
        throw Error(ErrorCode::InvalidArgument, "--key '" + text + "': frame is not a number");
    }
    key.look = loadLook(text.substr(colon + 1));
    return key;
}

// The keys bracket and blend as the runtime's keyframes do (runtime/world/keyframe_bracket.h,
// runtime/look/look_blend.h).
Look lookAtFrame(const std::vector<LookKey>& keys, int frame, const basis::BakeDescription& d) {
    const world::KeyframeBracket bracket = world::bracketKeyframes(keys, frame);
    if (bracket.lo == bracket.hi) return keys[bracket.lo].look;
    return interpolateLooks(keys[bracket.lo].look, keys[bracket.hi].look, bracket.t, d.bins, d.rbf_width);
}

}  // namespace

void registerAnimateCommand(CLI::App& app) {
    struct Args {
        std::string package, out_dir;
        std::vector<std::string> keys;
        double exposure = 0.0;
        int columns = 4;
        bool exr = false;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = app.add_subcommand("animate", "Render every frame with looks keyframed across the sequence");
    cmd->add_option("PACKAGE", args->package, ".firelook package")->required()->check(CLI::ExistingFile);
    cmd->add_option("--key", args->keys, "keyframe FRAME:LOOK.json (repeat; blended linearly in between)")->required();
    addOutputOption(*cmd, args->out_dir, "output folder (created)", {"--out-dir"})->required();
    cmd->add_option("--exposure", args->exposure, "PNG exposure in stops")->capture_default_str();
    cmd->add_option("--columns", args->columns, "contact sheet columns")->check(CLI::Range(1, 64))->capture_default_str();
    cmd->add_flag("--exr", args->exr, "also write linear premultiplied EXR frames");
    cmd->callback([args] {
        const basis::BasisReader package = basis::BasisReader::open(args->package);
        const basis::BakeDescription& d = package.description();
        std::vector<LookKey> keys;
        for (const std::string& k : args->keys) keys.push_back(parseKey(k));
        std::sort(keys.begin(), keys.end(), [](const LookKey& a, const LookKey& b) { return a.frame < b.frame; });
        for (size_t i = 1; i < keys.size(); ++i)
            if (keys[i].frame == keys[i - 1].frame)
                throw Error(ErrorCode::InvalidArgument, "two keys at frame " + std::to_string(keys[i].frame));

        StagingFolder staging(args->out_dir, "animate");
        image::WriteOptions png;
        png.png_exposure_stops = args->exposure;
        png.png_background = std::array<float, 3>{0.0f, 0.0f, 0.0f};  // opaque frames over black, as a viewer shows them
        std::vector<image::ImageRGBA> frames;
        ProgressBar bar("animate");
        for (size_t n = 0; n < d.frames.size(); ++n) {
            throwIfInterrupted();
            const int frame = d.frames[n].frame;
            const basis::ResidentFrame resident = package.loadResidentFrame(frame, std::pmr::get_default_resource());
            image::ImageRGBA image(d.width, d.height);
            basis::renderLookImage(d, resident, lookAtFrame(keys, frame, d), image.pixels);
            char name[32];
            std::snprintf(name, sizeof name, "frame_%04d", frame);
            image::writeImage(staging / (std::string(name) + ".png"), image, png);
            if (args->exr) image::writeImage(staging / (std::string(name) + ".exr"), image);
            frames.push_back(std::move(image));
            bar.update(double(n + 1) / d.frames.size(), "frame " + std::to_string(frame));
        }
        image::ContactSheetOptions sheet;
        sheet.write = png;
        image::writeContactSheet(staging / "contact_sheet.png", frames, args->columns, sheet);
        throwIfInterrupted();
        staging.commit();
        bar.finish(std::to_string(frames.size()) + " frames");
        const std::filesystem::path sheet_path = std::filesystem::path(args->out_dir) / "contact_sheet.png";
        std::printf("wrote %zu frames to %s/frame_NNNN.png%s and %s\n", frames.size(), args->out_dir.c_str(),
                    args->exr ? " (+ .exr)" : "", sheet_path.c_str());
    });
}

}  // namespace firelook::cli
