#include "bake/storage_target.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include "basis/source_balance.h"
#include "common/error.h"
#include "package/container_writer.h"

namespace firelook::bake {
namespace {

// The q grid of a size target: q = 2^(k / kStepsPerOctave) for k in [kLowest, kHighest].
constexpr int kStepsPerOctave = 8;
constexpr int kLowest = -4 * kStepsPerOctave;   // q = 1/16
constexpr int kHighest = 6 * kStepsPerOctave;   // q = 64

// --target-error: the fractions of E given to the storage error (the rest, in squares, to the
// truncation). Storing U and S V^T on a grid of error s costs about log2(1/s) bits a value, and
// the rank falls slowly as t grows, so the best split is usually a small storage share; five
// candidates cover it.
constexpr double kStorageShares[] = {0.1, 0.2, 0.3, 0.45, 0.6};

// What the index and each frame's META entries cost beside the shared META text: 3 index entries
// and an errors, source and frame record per frame, generously rounded up (their text is ~1 KiB).
constexpr uint64_t kPerFrameOverhead = 4096;
constexpr uint64_t kFixedOverhead = 4096;  // header, index header, alignment

double storageError(const CompressedFrame& c, const basis::EncodedFrame& e) {
    return std::hypot(c.quantisation_error, e.u_error, e.svt_error);
}

struct Candidate {
    CompressedFrame compressed;
    basis::EncodedFrame encoded;
    CompressionSettings compression;
    basis::FrameCodecSettings storage;
    uint64_t bytes = 0;
    double predicted = 0.0;
};

class CandidateEncoder {
  public:
    // `measure`: find each candidate's stored bytes (a target compares them); without a target the
    // one encoding is written as it is and the writer's own compression gives its bytes.
    CandidateEncoder(const basis::BakeDescription& description, const std::function<bool()>& keep_going, bool measure)
        : description_(description), keep_going_(keep_going), measure_(measure) {}

    Candidate encode(const CompressedFrame& full, int rank, const CompressionSettings& compression,
                     const basis::FrameCodecSettings& storage) {
        if (keep_going_ && !keep_going_()) throw Error(ErrorCode::Cancelled, "cancelled");
        ++count;
        Candidate c;
        c.compressed = leadingColumns(full, std::min(rank, full.factors.rank));
        c.compression = compression;
        c.storage = storage;
        c.encoded = basis::encodeFrame(description_, c.compressed.factors, storage);
        if (measure_)
            c.bytes = meter_.storedBytes(c.encoded.u) + meter_.storedBytes(c.encoded.svt) +
                      meter_.storedBytes(c.encoded.depths);
        c.predicted = std::hypot(c.compressed.truncation_error, storageError(c.compressed, c.encoded));
        return c;
    }
    int count = 0;

  private:
    const basis::BakeDescription& description_;
    const std::function<bool()>& keep_going_;
    bool measure_;
    package::StoredSizeMeter meter_;
};

FramePrecision finish(Candidate&& c, int candidates, double quality_scale, bool met) {
    FramePrecision out;
    out.compressed = std::move(c.compressed);
    out.encoded = std::move(c.encoded);
    out.compression = c.compression;
    out.storage = c.storage;
    out.quality_scale = quality_scale;
    out.stored_bytes = c.bytes;
    out.predicted_error = c.predicted;
    out.target_met = met;
    out.candidates = candidates;
    return out;
}

double qOfStep(int k) { return std::exp2(double(k) / kStepsPerOctave); }

// An error target's finest truncation: what is left of it beside the largest storage share.
double finestTruncationForError(double target) {
    const double largest = kStorageShares[std::size(kStorageShares) - 1];
    return target * std::sqrt(1.0 - largest * largest);
}

// Where a frame's factors come from: the spectrum that sizes the truncation, and the factors cut to
// a rank (the traced basis decomposed at that rank, or a stored frame's leading columns).
struct FrameSource {
    const FrameSpectrum& spectrum;
    std::function<CompressedFrame(int rank)> factors;
};

FramePrecision forError(const FrameSource& source, const CompressionSettings& compression,
                        const basis::FrameCodecSettings& storage, double target, CandidateEncoder& encoder) {
    const FrameSpectrum& spectrum = source.spectrum;
    // U once, at the largest rank any split needs (the smallest truncation share).
    CompressionSettings finest = compression;
    finest.target_relative_error = finestTruncationForError(target);
    const CompressedFrame full = source.factors(truncationRank(spectrum, finest));
    // The fewest bytes among the splits that meet the target; if none does (the rank cap), the
    // smallest predicted error.
    std::optional<Candidate> best;
    const auto meets = [&](const Candidate& c) { return c.predicted <= target * (1.0 + 1e-9); };
    for (double share : kStorageShares) {
        CompressionSettings c = compression;
        c.target_relative_error = target * std::sqrt(1.0 - share * share);
        const int rank = truncationRank(spectrum, c);
        // The half-precision rounding of U is part of the storage error and cannot be undone; the
        // grids get what is left of the share.
        const double half = leadingColumns(full, rank).quantisation_error;
        const double left = share * target;
        if (!(left > 1.05 * half)) continue;
        basis::FrameCodecSettings s = storage;
        s.basis_error = std::sqrt(left * left - half * half);
        Candidate candidate = encoder.encode(full, rank, c, s);
        const bool better = !best || (meets(candidate) && (!meets(*best) || candidate.bytes < best->bytes)) ||
                            (!meets(candidate) && !meets(*best) && candidate.predicted < best->predicted);
        if (better) best = std::move(candidate);
    }
    if (!best) {  // every share is below U's half-precision rounding: the finest grids allowed
        basis::FrameCodecSettings s = storage;
        s.basis_error = std::max(1e-6, target * 0.1);
        best = encoder.encode(full, full.factors.rank, finest, s);
    }
    const bool met = meets(*best);
    return finish(std::move(*best), encoder.count, 1.0, met);
}

FramePrecision forSize(const FrameSource& source, const CompressionSettings& compression,
                       const basis::FrameCodecSettings& storage, uint64_t share, CandidateEncoder& encoder) {
    const FrameSpectrum& spectrum = source.spectrum;
    const auto scale = qOfStep;
    CompressionSettings finest = compression;
    finest.target_relative_error *= scale(kLowest);
    const CompressedFrame full = source.factors(truncationRank(spectrum, finest));
    const auto at = [&](int k) {
        const double q = scale(k);
        CompressionSettings c = compression;
        c.target_relative_error *= q;
        basis::FrameCodecSettings s = storage;
        s.alpha_error *= q;
        s.footprint_error *= q;
        s.basis_error *= q;
        return encoder.encode(full, truncationRank(spectrum, c), c, s);
    };
    // Smallest k whose bytes fit: bracket with k = 0 (the configured settings), then bisect.
    Candidate middle = at(0);
    int lo, hi;  // bytes(hi) fits, bytes(lo) does not (or lo is one below the grid)
    std::optional<Candidate> fitting;
    if (middle.bytes <= share) {
        hi = 0;
        fitting = std::move(middle);
        Candidate lowest = at(kLowest);
        if (lowest.bytes <= share) return finish(std::move(lowest), encoder.count, scale(kLowest), true);
        lo = kLowest;
    } else {
        lo = 0;
        Candidate highest = at(kHighest);
        if (highest.bytes > share) return finish(std::move(highest), encoder.count, scale(kHighest), false);
        hi = kHighest;
        fitting = std::move(highest);
    }
    while (hi - lo > 1) {
        const int mid = lo + (hi - lo) / 2;
        Candidate c = at(mid);
        if (c.bytes <= share) {
            hi = mid;
            fitting = std::move(c);
        } else {
            lo = mid;
        }
    }
    return finish(std::move(*fitting), encoder.count, scale(hi), true);
}

}  // namespace

uint64_t frameShareBytes(const StorageTarget& target, size_t sequence_frames, uint64_t shared_metadata_bytes) {
    const uint64_t frames = std::max<size_t>(sequence_frames, 1);
    const uint64_t overhead = kFixedOverhead + shared_metadata_bytes + frames * kPerFrameOverhead;
    if (target.package_bytes <= overhead + frames * 1024)
        throw Error(ErrorCode::InvalidArgument, "--target-size " + std::to_string(target.package_bytes) +
                                                    " bytes leaves almost nothing for " +
                                                    std::to_string(frames) + " frames once the metadata (" +
                                                    std::to_string(overhead) + " bytes) is counted");
    return (target.package_bytes - overhead) / frames;
}

FramePrecision chooseFramePrecision(const FrameBasis& basis, int frame, const basis::BakeDescription& description,
                                    const CompressionSettings& compression, const basis::FrameCodecSettings& storage,
                                    const StorageTarget& target, uint64_t frame_share_bytes,
                                    const std::function<bool()>& keep_going) {
    // The finest truncation any candidate below tries: the spectrum need hold no more pairs.
    const double finest = target.basis_error > 0.0    ? finestTruncationForError(target.basis_error)
                          : target.package_bytes > 0 ? compression.target_relative_error * qOfStep(kLowest)
                                                     : compression.target_relative_error;
    const FrameSpectrum spectrum = frameSpectrum(basis, {description.columnsPerPoint(), description.bins.count},
                                                 {finest, compression.max_rank});
    CandidateEncoder encoder(description, keep_going, target.active());
    const FrameSource source{spectrum, [&](int rank) { return compressFrameBasis(basis, frame, spectrum, rank); }};
    if (target.basis_error > 0.0) return forError(source, compression, storage, target.basis_error, encoder);
    if (target.package_bytes > 0) return forSize(source, compression, storage, frame_share_bytes, encoder);
    const CompressedFrame full = compressFrameBasis(basis, frame, spectrum, truncationRank(spectrum, compression));
    return finish(encoder.encode(full, full.factors.rank, compression, storage), encoder.count, 1.0, true);
}

StoredFrameErrors storedFrameErrors(const basis::FrameFactors& factors, double truncation_error,
                                    double storage_error, const BasisSources& sources) {
    StoredFrameErrors out;
    out.frame.factors = factors;
    // Row m of S V^T D (D balances the sources as the bake's SVD did, basis/source_balance.h) has
    // the norm s_m (U's columns are orthonormal up to their storage error).
    const size_t columns = static_cast<size_t>(factors.columns), kinds = static_cast<size_t>(sources.columns_per_point);
    const bool balanced = kinds > 0 && columns % kinds == 0;
    const std::vector<double> factor =
        balanced ? basis::svtSourceBalance(factors.svt, factors.rank, sources.columns_per_point, sources.bins)
                 : std::vector<double>{};
    std::vector<double> energy(static_cast<size_t>(factors.rank), 0.0);
    for (size_t j = 0; j < columns; ++j)
        for (size_t m = 0; m < energy.size(); ++m) {
            const double v = factors.svt[j * factors.rank + m] * (balanced ? factor[j % kinds] : 1.0);
            energy[m] += v * v;
        }
    double kept = 0.0;
    for (double e : energy) kept += e;
    const double t2 = std::min(truncation_error * truncation_error, 0.999999);
    const double total = kept / (1.0 - t2);
    // The energy the bake dropped, as one value after the kept ones: every rank keeps it dropped.
    for (double e : energy) out.frame.singular_values.push_back(std::sqrt(e));
    out.frame.singular_values.push_back(std::sqrt(total * t2));
    // The storage error already in the frame, shared among the columns by their energy: cutting
    // columns takes their share with them; the rest stays (repack cannot restore precision).
    for (double e : energy) out.frame.column_quantisation.push_back(total > 0.0 ? storage_error * storage_error * e / kept : 0.0);
    out.spectrum.columns = factors.rank;
    out.spectrum.total = total;
    for (size_t m = energy.size(); m-- > 0;) out.spectrum.eigenvalues.push_back(energy[m]);
    return out;
}

FramePrecision chooseStoredFramePrecision(const StoredFrameErrors& stored, const basis::BakeDescription& description,
                                          const CompressionSettings& compression,
                                          const basis::FrameCodecSettings& storage, const StorageTarget& target,
                                          uint64_t frame_share_bytes, const std::function<bool()>& keep_going) {
    CandidateEncoder encoder(description, keep_going, target.active());
    const CompressedFrame& all = stored.frame;
    const FrameSource source{stored.spectrum,
                             [&](int rank) { return leadingColumns(all, std::min(rank, all.factors.rank)); }};
    if (target.basis_error > 0.0) return forError(source, compression, storage, target.basis_error, encoder);
    if (target.package_bytes > 0) return forSize(source, compression, storage, frame_share_bytes, encoder);
    return finish(encoder.encode(all, all.factors.rank, compression, storage), encoder.count, 1.0, true);
}

void checkStoredError(int frame, const basis::EncodedFrame& encoded, const basis::FrameCodecSettings& storage) {
    const double stored = std::hypot(encoded.u_error, encoded.svt_error);
    // A bound finer than the default may be out of the 16-bit grids' reach on any frame; the target
    // chooser reports that as not met. Failing is kept for error beyond the default's reach.
    const double bound = std::max(storage.basis_error, basis::FrameCodecSettings{}.basis_error);
    if (!(stored <= 2.0 * bound))
        throw Error(ErrorCode::Limit,
                    "frame " + std::to_string(frame) + ": storing its basis adds a relative error of " +
                        std::to_string(stored) + ", more than twice its bound " + std::to_string(bound) +
                        " (U " + std::to_string(encoded.u_error) + ", S V^T " + std::to_string(encoded.svt_error) +
                        "): its values span more than the codec's 16-bit grids hold; clamp the input "
                        "(--clamp-extreme) or look for voxels far brighter than the rest");
}

}  // namespace firelook::bake
