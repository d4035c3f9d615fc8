// firelook repack IN.firelook -o OUT.firelook [--alpha-error E] [--footprint-error E] [--basis-error E]
// Stores a package's frames again with the frame codec at the given precision, without baking:
// packages of layout 1 become layout 2, and a package can trade size for error after the fact.
// The errors add up: repacking a layout-2 package adds the new quantisation to the old one.
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "basis/basis_package.h"
#include "cli/commands.h"
#include "cli/interrupt.h"
#include "cli/output_option.h"
#include "cli/progress_bar.h"

namespace firelook::cli {

void registerRepackCommand(CLI::App& app) {
    struct Args {
        std::string input, output;
        basis::FrameCodecSettings storage;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = app.add_subcommand("repack", "Store a package's frames again at another precision (no baking)");
    cmd->add_option("PACKAGE", args->input, "input .firelook")->required()->check(CLI::ExistingFile);
    addOutputOption(*cmd, args->output, "output package (.firelook)", {"--output"})->required();
    cmd->add_option("--alpha-error", args->storage.alpha_error,
                    "largest alpha error the stored optical depths may add, for any look in the baked range")
        ->capture_default_str();
    cmd->add_option("--footprint-error", args->storage.footprint_error,
                    "pixels whose footprint rays give the alpha of their mean ray within this store the mean ray only")
        ->capture_default_str();
    cmd->add_option("--basis-error", args->storage.basis_error,
                    "Frobenius error that storing U and S V^T may add to the basis, relative to its norm")
        ->capture_default_str();
    cmd->callback([args] {
        const basis::BasisPackage in = basis::BasisPackage::open(args->input);
        const basis::BakeDescription& d = in.description();
        nlohmann::ordered_json extra = nlohmann::ordered_json::parse(in.metadataJson());
        for (const char* key : {"format", "version", "bake"}) extra.erase(key);
        package::PackageWriter writer(args->output);
        ProgressBar bar("repack");
        uint64_t before = 0, after = 0;
        for (const package::SectionInfo& s : in.reader().sections()) before += s.stored_size;
        nlohmann::ordered_json frames = nlohmann::ordered_json::array();
        for (size_t i = 0; i < d.frames.size(); ++i) {
            const int frame = d.frames[i].frame;
            const basis::StoredFrame stored = writeFrameFactors(writer, d, in.loadFrame(frame), args->storage);
            after += stored.bytes();
            // The fire lights do not depend on the storage precision: copied as stored.
            if (const package::SectionInfo* s = in.reader().find(basis::kSectionFireLights, static_cast<uint32_t>(frame)))
                after += writer.addStoredSection(*s, in.reader().stored(*s)).stored_size;
            frames.push_back({{"frame", frame},
                              {"storage_relative_error", std::hypot(stored.u_error, stored.svt_error)},
                              {"pixels_with_footprint_rays", stored.detailed_pixels},
                              {"alpha_storage_error_bound", stored.alpha_bound},
                              {"bytes", {{"u", stored.u_bytes}, {"svt", stored.svt_bytes}, {"depths", stored.depth_bytes}}}});
            bar.update(double(i + 1) / d.frames.size(), "frame " + std::to_string(frame));
            throwIfInterrupted();  // the writer deletes its temporary file
        }
        extra["repacked"] = {{"from_layout", in.layoutVersion()},
                             {"alpha_error", args->storage.alpha_error},
                             {"footprint_error", args->storage.footprint_error},
                             {"basis_error", args->storage.basis_error},
                             {"frames", frames}};
        writer.addMetadata(basis::makeMetadata(d, extra.dump()));
        writer.commit();
        bar.finish(std::to_string(d.frames.size()) + " frames");
        std::printf("wrote %s: %zu frames, frame sections %.2f MiB (were %.2f MiB in all sections)\n",
                    args->output.c_str(), d.frames.size(), after / 1048576.0, before / 1048576.0);
    });
}

}  // namespace firelook::cli
