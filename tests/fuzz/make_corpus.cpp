// Writes the seed corpus of the fuzz targets: fuzz_make_corpus <tests/fuzz/corpus>.
// Run by hand after a change of the package layout or look format; the output is kept in the
// repository (each file well under 20 KB). Hand-written seeds (sample looks) live beside them.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "../vdb/vdb_test_files.h"
#include "basis/basis_package.h"
#include "look/look.h"
#include "package/container_writer.h"

namespace {

using namespace firelook;
namespace fs = std::filesystem;

void writeText(const fs::path& file, const std::string& text) {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out << text;
}

std::string readBytes(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

// A 4x4 image, 2 bins over [0, 3], one light, T_c in {0.5, 1.5}: 2 grid points x 3 columns.
basis::BakeDescription description(int frames, int rank) {
    basis::BakeDescription d;
    d.bins = {0.0, 3.0, 2};
    d.rbf_width = kDefaultRbfWidth;
    d.albedo = 0.7;
    d.axes = {{0.5, 1.5}, {2.0}, {1.0}};
    d.alpha_thresholds = {0.5, 1.5};
    d.light_directions = {{0.0, -1.0, 0.0}};
    d.width = 4;
    d.height = 4;
    for (int f = 1; f <= frames; ++f) d.frames.push_back({f, rank});
    Look look = defaultLook();
    look.albedo = d.albedo;
    look.temperature_threshold = 1.0;
    look.smoke_extinction = 2.0;
    look.flame_extinction = 1.0;
    d.default_look_json = lookToJson(look);
    return d;
}

basis::FrameFactors factors(const basis::BakeDescription& d, int frame, int rank) {
    basis::FrameFactors f;
    f.frame = frame;
    f.pixels = d.pixelCount();
    f.columns = d.columnCount();
    f.rank = rank;
    for (int i = 0; i < f.pixels * rank; ++i) f.u_half.push_back(static_cast<uint16_t>(0x3000 + 37 * i % 0x0C00));  // 0.125..0.9
    for (int i = 0; i < f.columns * rank; ++i) f.svt.push_back(0.5f + 0.25f * float(i % 5) - 0.3f * float(i % 2));
    for (int p = 0; p < f.pixels; ++p) f.depth_b.push_back(0.1f * float(p % 7));
    for (std::size_t a = 0; a < d.alpha_thresholds.size(); ++a)
        for (int p = 0; p < f.pixels; ++p) f.depth_a.push_back(0.05f * float(p % 5) - 0.1f * float(a));
    return f;
}

void writeBasisPackage(const fs::path& file, int frames, int rank, package::Codec codec) {
    const basis::BakeDescription d = description(frames, rank);
    package::ContainerWriter writer(file, package::WriterOptions{3});
    for (int frame = 1; frame <= frames; ++frame) {
        const basis::FrameFactors f = factors(d, frame, rank);
        if (codec == package::Codec::Zstd) {
            basis::writeFrameFactors(writer, d, f);
        } else {
            const basis::EncodedFrame e = basis::encodeFrame(d, f, {});
            writer.addSection(basis::kSectionU, frame, e.u, codec);
            writer.addSection(basis::kSectionSVt, frame, e.svt, codec);
            writer.addSection(basis::kSectionDepths, frame, e.depths, codec);
        }
    }
    writer.addMetadata(basis::makeMetadata(d, R"({"provenance": {"tool": "fuzz_make_corpus"}})"));
    writer.commit();
}

void packageCorpus(const fs::path& dir) {
    writeBasisPackage(dir / "basis_zstd_2frames.firelook", 2, 2, package::Codec::Zstd);
    writeBasisPackage(dir / "basis_raw_1frame.firelook", 1, 3, package::Codec::Raw);
    writeBasisPackage(dir / "basis_rank0.firelook", 1, 0, package::Codec::Zstd);
    {
        // A container that is not a basis package: other metadata, an optional unknown section.
        package::ContainerWriter writer(dir / "container_other.firelook");
        const std::string text = "opaque payload";
        writer.addSection(package::makeFourCC('X', 'T', 'R', 'A'), 7, std::as_bytes(std::span(text)),
                          package::Codec::Raw, false);
        writer.addMetadata(R"({"format": "something-else"})");
        writer.commit();
    }
    const std::string whole = readBytes(dir / "basis_zstd_2frames.firelook");
    writeText(dir / "basis_truncated_half.firelook", whole.substr(0, whole.size() / 2));
    writeText(dir / "basis_truncated_header.firelook", whole.substr(0, 40));
    // Structured seeds (fuzz_package_reader mode 3): META text, NUL, flag byte, payload.
    const basis::BakeDescription d = description(1, 2);
    std::string payload(1, '\0');
    for (int i = 0; i < 64; ++i) payload += static_cast<char>((i * 29 + 3) & 0xFF);
    writeText(dir / "meta_basis.bin", basis::makeMetadata(d, "") + std::string(1, '\0') + payload);
    payload[0] = '\3';  // raw codec, sizes from the payload
    writeText(dir / "meta_basis_sizes.bin", basis::makeMetadata(d, "") + std::string(1, '\0') + payload);
    const float special[] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                             -std::numeric_limits<float>::infinity(), -1.0f, 1e30f};
    std::string floats(1, '\0');
    floats.append(reinterpret_cast<const char*>(special), sizeof special);
    writeText(dir / "meta_basis_nonfinite.bin", basis::makeMetadata(d, "") + std::string(1, '\0') + floats);
}

void lookCorpus(const fs::path& dir) {
    writeText(dir / "default.json", lookToJson(defaultLook()));
    Look bins = defaultLook();
    bins.emission = EmissionBins{{Rgb(0.0f), Rgb(0.0f), Rgb(1.0f, 0.5f, 0.1f), Rgb(8.0f, 4.0f, 1.0f)}};
    writeText(dir / "bins4.json", lookToJson(bins));
    Look preset = defaultLook();
    preset.emission = EmissionPreset{"fire", 2.5};
    preset.light_irradiance.push_back(Rgb(0.2f, 0.3f, 0.5f));
    writeText(dir / "preset_two_lights.json", lookToJson(preset));
    Look step = defaultLook();
    step.emission = EmissionStops{{{1.5, Rgb(0.0f)}, {1.5, Rgb(20.0f, 10.0f, 2.0f)}}};
    step.smoke_extinction = 0.0;
    step.albedo = 1.0;
    writeText(dir / "step_ks0_albedo1.json", lookToJson(step));
}

// Like vdb::testing::writeVdb, with zip compression: the stored leaves shrink to a few KB.
void writeSmallVdb(const fs::path& path, const openvdb::GridPtrVec& grids, bool with_stats = true) {
    openvdb::io::File file(path.string());
    file.setCompression(openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK);
    file.setGridStatsMetadataEnabled(with_stats);
    file.write(grids);
    file.close();
}

void vdbCorpus(const fs::path& dir) {
    using namespace firelook::vdb::testing;
    Voxels density, temperature, dirty;
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j)
            for (int k = 0; k < 6; ++k) {
                density.push_back({{i, j, k}, 0.1f * float(1 + (i + j + k) % 5)});
                temperature.push_back({{i, j, k}, 0.5f * float(i)});
            }
    dirty = density;
    dirty[3].second = std::numeric_limits<float>::quiet_NaN();
    dirty[9].second = std::numeric_limits<float>::infinity();
    dirty[20].second = -2.0f;
    writeSmallVdb(dir / "small.vdb", {makeGrid("density", density), makeGrid("temperature", temperature)});
    writeSmallVdb(dir / "small_no_stats.vdb", {makeGrid("density", density), makeGrid("flame", temperature, 0.1)}, false);
    writeSmallVdb(dir / "dirty.vdb", {makeGrid("density", dirty), makeGrid("heat", temperature)});
    writeSmallVdb(dir / "density_only.vdb", {makeGrid("density", density)});
    writeSmallVdb(dir / "different_transforms.vdb", {makeGrid("density", density, 0.1), makeGrid("temperature", temperature, 0.2)});
    const std::string whole = readBytes(dir / "small.vdb");
    for (const int percent : {10, 50, 90})
        writeText(dir / ("small_truncated_" + std::to_string(percent) + ".vdb"),
                  whole.substr(0, whole.size() * percent / 100));
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s tests/fuzz/corpus\n", argv[0]);
        return 2;
    }
    const fs::path root = argv[1];
    for (const char* target : {"package_reader", "look_file", "vdb_sequence"}) fs::create_directories(root / target);
    packageCorpus(root / "package_reader");
    lookCorpus(root / "look_file");
    vdbCorpus(root / "vdb_sequence");
    std::printf("corpus written under %s\n", root.string().c_str());
    return 0;
}
