// firelook reference SEQUENCE --frame F [--look L.json] [--scene S.gltf | --camera ...]
//                    [--size WxH] [--light-dir X,Y,Z [--light-irradiance R,G,B]]... --spp N -o IMG
// Path-traced ground truth of exactly the model a bake with the same flags uses
// (same bins, camera and lights; without --look, the same default look).
#include <cstdio>

#include "bake/bake_pipeline.h"
#include "cli/commands.h"
#include "cli/interrupt.h"
#include "cli/light_direction_option.h"
#include "cli/output_option.h"
#include "cli/progress_bar.h"
#include "cli/scene_options.h"
#include "common/error.h"
#include "image/image_io.h"
#include "look/look.h"
#include "reference/frame_medium.h"
#include "render/reference_tracer.h"

namespace firelook::cli {

void registerReferenceCommand(CLI::App& app) {
    struct Args {
        std::string sequence, look, out;
        int frame = 0, spp = 64;
        uint64_t seed = 1;
        SceneFlags scene;
        LightDirectionFlags light;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = app.add_subcommand("reference", "Path-trace one frame with a look (unbiased ground truth)");
    cmd->add_option("SEQUENCE", args->sequence, "folder of .vdb files or a pattern such as fire_####.vdb")->required();
    cmd->add_option("--frame", args->frame, "frame number")->required();
    cmd->add_option("--look", args->look, "look file (default: the default look a bake records)")
        ->check(CLI::ExistingFile);
    cmd->add_option("--spp", args->spp, "samples per pixel")->required()->check(CLI::Range(1, 1 << 20));
    cmd->add_option("--seed", args->seed, "random seed")->capture_default_str();
    addOutputOption(*cmd, args->out, "output image (.exr or .png)")->required();
    addSceneFlags(*cmd, args->scene);
    addLightDirectionFlags(
        *cmd, args->light,
        "in place of the six-way or sphere lights (needs --lights six-way or sphere, as the "
        "bake it judges)");
    cmd->callback([cmd, args] {
        const bake::BakeConfig config = makeBakeConfig(*cmd, args->scene);
        const vdb::VdbSequence sequence = vdb::VdbSequence::open(args->sequence, config.read);
        const bake::SceneSetup scene = bake::resolveScene(sequence, config.scene);
        const std::vector<basis::RunTimeLight> lights = runTimeLights(args->light);
        const int first =
            scene.six_way_first_light >= 0 ? scene.six_way_first_light : scene.sphere_first_light;
        if (!lights.empty() && first < 0)
            throw Error(
                ErrorCode::InvalidArgument,
                "--light-dir takes the place of the six-way or sphere lights: pass --lights six-way or "
                "--lights sphere");
        const basis::BakeDescription d = bake::describeBake(sequence, config, scene);
        const Look look = args->look.empty() ? parseLook(d.default_look_json, "default look") : loadLook(args->look);
        LookModel model = makeLookModel(look, d.bins, d.rbf_width, d.light_directions);
        if (!lights.empty()) {
            // The lights themselves, where render and the runtime weight the six-way or sphere
            // lights' columns (they are the last lights).
            model.lights.erase(model.lights.begin() + first, model.lights.end());
            for (const basis::RunTimeLight& light : lights)
                model.lights.push_back({basis::checkedUnitDirection(light), light.irradiance});
        }
        throwIfInterrupted();
        const render::Medium medium = reference::mediumFromFrame(sequence.load(args->frame));
        throwIfInterrupted();

        render::ReferenceSettings settings;
        settings.samples_per_pixel = args->spp;
        settings.seed = args->seed;
        settings.stop_requested = interruptRequested;
        ProgressBar bar("reference");
        const render::ReferenceResult result =
            render::renderReference(medium, model, scene.camera, settings, [&](double fraction) {
                bar.update(fraction, std::to_string(args->spp) + " spp");
                return !interruptRequested();
            });
        throwIfInterrupted();  // before anything is written: an existing output keeps its bytes
        bar.finish();
        image::ImageRGBA image(result.image.width, result.image.height);
        image.pixels = result.image.rgba;
        image::writeImage(args->out, image);
        std::printf("wrote %s: %dx%d, %d spp, %.1f s, estimated relative RMSE %.4f%s\n", args->out.c_str(),
                    image.width, image.height, args->spp, result.seconds, result.estimated_relative_rmse,
                    result.sanitized_samples ? " (some non-finite samples were dropped)" : "");
    });
}

}  // namespace firelook::cli
