// firelook compare IMAGE REFERENCE [--json]: the error measures of docs/testing.md
// between two images of the same size (relative RMSE over linear RGB,
// maximum absolute alpha error).
#include <cstdio>

#include "cli/commands.h"
#include "common/error.h"
#include "image/image_io.h"
#include "render/render_image.h"

namespace firelook::cli {
namespace {

render::RenderImage toRenderImage(const image::ImageRGBA& image) { return {image.width, image.height, image.pixels}; }

}  // namespace

void registerCompareCommand(CLI::App& app) {
    struct Args {
        std::string image, reference;
        bool json = false;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = app.add_subcommand("compare", "Relative RMSE and max alpha error of an image against a reference");
    cmd->add_option("IMAGE", args->image, "image to judge")->required()->check(CLI::ExistingFile);
    cmd->add_option("REFERENCE", args->reference, "reference image")->required()->check(CLI::ExistingFile);
    cmd->add_flag("--json", args->json, "print JSON");
    cmd->callback([args] {
        const image::ImageRGBA a = image::readImage(args->image), r = image::readImage(args->reference);
        if (a.width != r.width || a.height != r.height)
            throw Error(ErrorCode::InvalidArgument, args->image + " is " + std::to_string(a.width) + "x" +
                                                        std::to_string(a.height) + " but " + args->reference +
                                                        " is " + std::to_string(r.width) + "x" +
                                                        std::to_string(r.height));
        const double rmse = render::relativeRmse(toRenderImage(a), toRenderImage(r));
        const double alpha = render::maxAlphaError(toRenderImage(a), toRenderImage(r));
        if (args->json)
            std::printf("{\"relative_rmse\": %.6g, \"max_alpha_error\": %.6g}\n", rmse, alpha);
        else
            std::printf("relative RMSE %.4f, max alpha error %.4f\n", rmse, alpha);
    });
}

}  // namespace firelook::cli
