// Choosing how precisely a frame is stored from what the user wants of the package:
// `firelook bake --target-size SIZE` (the whole sequence's package within SIZE bytes) or
// `--target-error E` (each frame's stored basis within a relative Frobenius error E).
//
// The stored basis B' = U' S' V'^T differs from the traced B by two independent parts: the SVD's
// truncation t (the dropped singular values) and the storage s (U in half precision, then W = U S
// and S V^T on uniform grids; basis_error bounds the grids' part). They are orthogonal enough to
// add in squares, so the predicted error is hypot(t, s), the figure the bake reports per frame.
//
// --target-error E: the split of E^2 between t^2 and s^2 that stores the fewest bytes is found by
// trying a few splits (the rank falls as t grows, the grids coarsen as s grows); the depths for
// exact alpha are not touched (their bound is --alpha-error's business).
//
// --target-size: every frame of the sequence gets an equal share of the bytes (after META and the
// index), so a frame's bytes never depend on which other frames a shard bakes and shards still
// merge into the one-shot package. Within its share a frame takes the finest quality it can:
// one factor q scales all four error settings (truncation, basis, alpha and footprint errors)
// from the configured ones, and q is the smallest on a log2 grid of eighths in [1/16, 64] whose
// encoding fits (bisection; bytes fall as q grows). A frame that does not fit even at q = 64 is
// stored at q = 64 and reported as over its share.
#pragma once

#include <cstdint>
#include <functional>

#include "bake/basis_compression.h"
#include "bake/basis_tracer.h"
#include "basis/bake_description.h"
#include "basis/frame_codec.h"

namespace firelook::bake {

struct StorageTarget {
    uint64_t package_bytes = 0;  // --target-size; 0 = none
    double basis_error = 0.0;    // --target-error; 0 = none
    bool active() const { return package_bytes > 0 || basis_error > 0.0; }
};

// One frame's stored form as chosen, and what it predicts.
struct FramePrecision {
    CompressedFrame compressed;
    basis::EncodedFrame encoded;
    CompressionSettings compression;    // the settings it was stored with
    basis::FrameCodecSettings storage;
    double quality_scale = 1.0;         // --target-size: q, the factor on every error setting
    uint64_t stored_bytes = 0;          // with a target: the frame's three sections in the file (after zstd)
    double predicted_error = 0.0;       // hypot(truncation, storage), relative to ||B||_F
    bool target_met = true;             // false: over its share, or the error needs more than max_rank
    int candidates = 1;                 // encodings tried
};

// The bytes each frame may take for --target-size: (package_bytes - what META and the index cost)
// / the sequence's frame count. `shared_metadata_bytes`: the shared META text, a bound on its
// compressed size. Throws an InvalidArgument Error when the target leaves no bytes for frames.
uint64_t frameShareBytes(const StorageTarget& target, size_t sequence_frames, uint64_t shared_metadata_bytes);

// Without an active target: the frame as `compression` and `storage` say. `frame_share_bytes` is
// frameShareBytes' figure (used only for a size target). `keep_going` is asked between candidates
// (false: throws a Cancelled Error, "cancelled").
FramePrecision chooseFramePrecision(const FrameBasis& basis, int frame, const basis::BakeDescription& description,
                                    const CompressionSettings& compression, const basis::FrameCodecSettings& storage,
                                    const StorageTarget& target, uint64_t frame_share_bytes,
                                    const std::function<bool()>& keep_going = {});

// Throws firelook::Error (Limit) naming the frame when storing it added more than twice the
// error `storage` allows to the basis (encoded.u_error, encoded.svt_error), or than the default
// FrameCodecSettings allow where `storage` asks for less (a target finer than the grids reach is
// reported by the chooser as not met, not failed: firelook repack --target-error 0.00001). The codec's grids hold
// 2^16 levels each: a factor whose largest value is beyond ~10^4 times its rms (one pixel or
// column far brighter than the rest) forces a coarser step than the bound needs, and the frame
// would render wrong while the bake reported it stored. Twice: the measured rounding error spreads
// about the uniform-noise estimate the steps are chosen by, on small frames by tens of percent.
void checkStoredError(int frame, const basis::EncodedFrame& encoded, const basis::FrameCodecSettings& storage);

// A frame already stored in a package (firelook repack), as the chooser sees it: the stored
// factors stand for the basis, their S V^T row norms for its singular values, and the errors the
// package records for it (its SVD truncation and storage errors, relative to the traced basis)
// stay in every prediction. Rank can only fall from the stored rank and the grids only coarsen:
// what the package no longer holds cannot be restored.
struct StoredFrameErrors {
    CompressedFrame frame;
    FrameSpectrum spectrum;  // no eigenvectors: the stored singular values squared and the total
};
StoredFrameErrors storedFrameErrors(const basis::FrameFactors& factors, double truncation_error,
                                    double storage_error, const BasisSources& sources = {});

// chooseFramePrecision for a stored frame.
FramePrecision chooseStoredFramePrecision(const StoredFrameErrors& stored, const basis::BakeDescription& description,
                                          const CompressionSettings& compression,
                                          const basis::FrameCodecSettings& storage, const StorageTarget& target,
                                          uint64_t frame_share_bytes, const std::function<bool()>& keep_going = {});

}  // namespace firelook::bake
