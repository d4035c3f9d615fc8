// firelook render PACKAGE --frame F [--look L.json] [--light-dir X,Y,Z [--light-irradiance R,G,B]]...
//                 -o IMG (.exr or .png)
#include <cstdio>

#include "basis/basis_package.h"
#include "basis/look_renderer.h"
#include "cli/commands.h"
#include "cli/interrupt.h"
#include "cli/light_direction_option.h"
#include "cli/output_option.h"
#include "image/image_io.h"
#include "look/look.h"

namespace firelook::cli {

void registerRenderCommand(CLI::App& app) {
    struct Args {
        std::string package, look, out;
        int frame = 0;
        double exposure = 0.0;
        LightDirectionFlags light;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = app.add_subcommand("render", "Recombine one frame of a package with a look into an image");
    cmd->add_option("PACKAGE", args->package, ".firelook package")->required()->check(CLI::ExistingFile);
    cmd->add_option("--frame", args->frame, "frame number")->required();
    cmd->add_option("--look", args->look, "look file (default: the look recorded in the package)")
        ->check(CLI::ExistingFile);
    addOutputOption(*cmd, args->out, "output image, .exr (linear premultiplied RGBA) or .png")->required();
    cmd->add_option("--exposure", args->exposure, "PNG exposure in stops")->capture_default_str();
    addLightDirectionFlags(*cmd, args->light,
                           "in place of the six-way or sphere lights of a bake with --lights six-way or "
                           "sphere (weighted, docs/cli.md \"Light from any direction\")");
    cmd->callback([args] {
        const basis::BasisReader package = basis::BasisReader::open(args->package);
        const basis::BakeDescription& d = package.description();
        Look look = args->look.empty() ? parseLook(d.default_look_json, args->package + " (default look)")
                                             : loadLook(args->look);
        const std::vector<basis::RunTimeLight> lights = runTimeLights(args->light);
        if (!lights.empty()) basis::applyRunTimeLights(d, lights, args->package, look.light_irradiance);
        // The resident form, as the runtime world draws it.
        const basis::ResidentFrame frame = package.loadResidentFrame(args->frame, std::pmr::get_default_resource());
        image::ImageRGBA image(d.width, d.height);
        basis::renderLookImage(d, frame, look, image.pixels);
        image::WriteOptions options;
        options.png_exposure_stops = args->exposure;
        throwIfInterrupted();
        image::writeImage(args->out, image, options);
        std::printf("wrote %s (%dx%d, frame %d, rank %d)\n", args->out.c_str(), d.width, d.height, args->frame,
                    frame.rank);
    });
}

}  // namespace firelook::cli
