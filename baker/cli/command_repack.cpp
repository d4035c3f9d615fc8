// firelook repack IN.firelook -o OUT.firelook [--alpha-error E] [--footprint-error E] [--basis-error E]
//                 [--target-size SIZE | --target-error E]
// Stores a package's frames again with the frame codec at the given precision, without baking:
// packages of layout 1 become layout 2, and a package can trade size for error after the fact.
// The errors add up: repacking a layout-2 package adds the new quantisation to the old one. The
// targets choose rank and precision per frame as `bake` does (bake/storage_target.h), from the
// stored factors: rank can only fall and precision only coarsen.
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "bake/bake_config.h"
#include "bake/storage_target.h"
#include "basis/basis_package.h"
#include "cli/commands.h"
#include "cli/interrupt.h"
#include "cli/output_option.h"
#include "cli/progress_bar.h"
#include "cli/storage_target_option.h"

namespace firelook::cli {
namespace {

nlohmann::ordered_json storedEntry(int frame, const basis::StoredFrame& stored) {
    return {{"frame", frame},
            {"storage_relative_error", std::hypot(stored.u_error, stored.svt_error)},
            {"pixels_with_footprint_rays", stored.detailed_pixels},
            {"alpha_storage_error_bound", stored.alpha_bound},
            {"bytes", {{"u", stored.u_bytes}, {"svt", stored.svt_bytes}, {"depths", stored.depth_bytes}}}};
}

// The errors the package records for a frame, relative to the traced basis: the bake's truncation
// and storage errors (META "errors"), and an earlier repack's storage error on top (they add in
// squares). A package that records none (written by other tools) counts as exact.
bake::StoredFrameErrors storedFrameErrors(const nlohmann::ordered_json& meta, int frame, const basis::FrameFactors& factors,
                                         const basis::BakeDescription& description) {
    double truncation = 0.0, storage = 0.0;
    for (const auto& e : meta.value("errors", nlohmann::ordered_json::array()))
        if (e.value("frame", -1) == frame) {
            truncation = e.value("svd_truncation_relative_error", 0.0);
            storage = e.value("storage_relative_error", 0.0);
        }
    if (meta.contains("repacked"))
        for (const auto& e : meta["repacked"].value("frames", nlohmann::ordered_json::array()))
            if (e.value("frame", -1) == frame) {
                storage = std::hypot(storage, e.value("storage_relative_error", 0.0));
                truncation = std::max(truncation, e.value("svd_truncation_relative_error", 0.0));
            }
    return bake::storedFrameErrors(factors, truncation, storage, {description.columnsPerPoint(), description.bins.count});
}

}  // namespace

void registerRepackCommand(CLI::App& app) {
    struct Args {
        std::string input, output;
        StorageTargetFlags target;
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
    addStorageTargetFlags(*cmd, args->target,
                          "aim the package at this size, e.g. 6M (binary units), as `bake --target-size` does: each frame "
                          "an equal share, at the finest precision that fits, by cutting rank and coarsening the storage of "
                          "the stored frame; it cannot restore precision the package does not hold",
                          "store each frame's basis within this relative error (the package's recorded truncation and "
                          "storage errors included), in the fewest bytes, as `bake --target-error` does; only errors above "
                          "what the package already holds can be met (rank only falls, precision only coarsens)");
    cmd->callback([cmd, args] {
        const bake::StorageTarget target = storageTarget(*cmd, args->target);
        const basis::BasisReader in = basis::BasisReader::open(args->input);
        basis::BakeDescription d = in.description();
        nlohmann::ordered_json extra = nlohmann::ordered_json::parse(in.metadataJson());
        for (const char* key : {"format", "version", "bake"}) extra.erase(key);
        // The truncation the package was baked with, which a size target scales like the bake does.
        bake::CompressionSettings compression;
        if (extra.contains("provenance") && extra["provenance"].contains("settings")) {
            const auto& c = extra["provenance"]["settings"].value("compression", nlohmann::ordered_json::object());
            compression.target_relative_error = c.value("target_relative_error", compression.target_relative_error);
            compression.max_rank = c.value("max_rank", compression.max_rank);
        }
        const uint64_t share =
            target.package_bytes > 0 ? bake::frameShareBytes(target, d.frames.size(), in.metadataJson().size()) : 0;
        package::ContainerWriter writer(args->output);
        ProgressBar bar("repack");
        uint64_t before = 0, after = 0;
        for (const package::SectionInfo& s : in.reader().sections()) before += s.stored_size;
        nlohmann::ordered_json frames = nlohmann::ordered_json::array();
        for (size_t i = 0; i < d.frames.size(); ++i) {
            const int frame = d.frames[i].frame;
            nlohmann::ordered_json entry;
            if (target.active()) {
                const bake::StoredFrameErrors errors = storedFrameErrors(extra, frame, in.loadFrame(frame), d);
                const bake::FramePrecision chosen = bake::chooseStoredFramePrecision(
                    errors, d, compression, args->storage, target, share,
                    [] { return !interruptRequested(); });
                bake::checkStoredError(frame, chosen.encoded, chosen.storage);
                const basis::StoredFrame stored = basis::writeEncodedFrame(writer, frame, chosen.encoded);
                d.frames[i].rank = chosen.compressed.factors.rank;
                after += stored.bytes();
                entry = storedEntry(frame, stored);
                entry["rank"] = chosen.compressed.factors.rank;
                entry["svd_truncation_relative_error"] = chosen.compressed.truncation_error;
                entry["predicted_error"] = chosen.predicted_error;
                entry["met"] = chosen.target_met;
                entry["quality_scale"] = chosen.quality_scale;
                entry["basis_error"] = chosen.storage.basis_error;
                entry["alpha_error"] = chosen.storage.alpha_error;
                entry["footprint_error"] = chosen.storage.footprint_error;
                if (!chosen.target_met)
                    std::fprintf(stderr, "frame %d: %s (predicted error %.3g)\n", frame,
                                 target.package_bytes > 0 ? "does not fit its share of --target-size"
                                                          : "--target-error is below what the package holds",
                                 chosen.predicted_error);
            } else {
                const basis::StoredFrame stored = writeFrameFactors(writer, d, in.loadFrame(frame), args->storage);
                after += stored.bytes();
                entry = storedEntry(frame, stored);
            }
            // The fire lights and probes do not depend on the storage precision: copied as stored.
            if (const package::SectionInfo* s = in.reader().find(basis::kSectionFireLights, static_cast<uint32_t>(frame)))
                after += writer.addStoredSection(*s, in.reader().stored(*s)).stored_size;
            if (const package::SectionInfo* s =
                    in.reader().find(basis::kSectionFireProbes, static_cast<uint32_t>(frame)))
                after += writer.addStoredSection(*s, in.reader().stored(*s)).stored_size;
            frames.push_back(entry);
            bar.update(double(i + 1) / d.frames.size(), "frame " + std::to_string(frame));
            throwIfInterrupted();  // the writer deletes its temporary file
        }
        extra["repacked"] = {{"from_layout", in.layoutVersion()},
                             {"alpha_error", args->storage.alpha_error},
                             {"footprint_error", args->storage.footprint_error},
                             {"basis_error", args->storage.basis_error},
                             {"frames", frames}};
        if (target.package_bytes > 0) extra["repacked"]["target_size"] = target.package_bytes;
        if (target.basis_error > 0.0) extra["repacked"]["target_error"] = target.basis_error;
        writer.addMetadata(basis::makeMetadata(d, extra.dump()));
        writer.commit();
        bar.finish(std::to_string(d.frames.size()) + " frames");
        std::printf("wrote %s: %zu frames, frame sections %.2f MiB (were %.2f MiB in all sections)\n",
                    args->output.c_str(), d.frames.size(), after / 1048576.0, before / 1048576.0);
    });
}

}  // namespace firelook::cli
