// How one frame's factors are stored (docs/package-format.md, "Frame codec"): quantised with
// error bounds chosen by the bake, predicted from their neighbours, and left to the container's
// zstd to entropy-code; pixels whose values are all 0 (outside the fire's footprint) are given as
// runs and have no codes (payload version 3). Encoding is deterministic (the same factors and settings give the same
// bytes); decoding checks every size against the description and never yields NaN.
//
// U is stored as W = U S (each column scaled by its singular value) on one uniform grid of step
// `u_step`, so the error added to the basis B = U S V^T is the same white error whatever the
// column: ||dB||_F = ||dW||_F, about u_step * sqrt(pixels * rank / 12). S V^T likewise on a grid
// of its own (||dB||_F = ||d(S V^T)||_F, U being orthonormal).
//
// Optical depths are stored through the companding g(O) = integral over [0, O] of
// max over k in [k_lo, k_hi] of k e^(-k x) dx, where [k_lo, k_hi] spans the package's baked
// extinctions: a step dg moves the alpha of one ray by at most c dg for any look in the axes'
// range (c = max(1, max k_f / min k_s); see depth_companding.cpp), so the alpha error of any pixel,
// for any look, is bounded by `alpha_error` whatever the depth.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "basis/bake_description.h"
#include "basis/depth_companding.h"
#include "basis/frame_factors.h"
#include "basis/resident_frame.h"

namespace firelook::basis {

struct FrameCodecSettings {
    // Largest alpha error the stored depths may add, per pixel and for any look in the axes'
    // range (on top of the footprint quadrature).
    double alpha_error = 0.001;
    // Pixels whose footprint rays all give the alpha of their mean ray within this (for every look
    // on or between the grid points) store only the mean ray; 0 keeps every ray that differs.
    double footprint_error = 0.001;
    // Frobenius error that storing U and S V^T may add to the basis B, relative to ||B||_F
    // (half of its square each), beside the SVD's truncation error.
    double basis_error = 0.0005;
};

// The bytes of the three sections of one frame, before the container's zstd, and what the
// quantisation cost.
struct EncodedFrame {
    std::vector<std::byte> u;       // UFAC payload
    std::vector<std::byte> svt;     // SVTF payload
    std::vector<std::byte> depths;  // ODEP payload
    double u_step = 0.0;            // grid step of W = U S
    double u_error = 0.0;           // ||dW||_F / ||S||, measured
    double svt_step = 0.0;          // grid step of S V^T
    double svt_error = 0.0;         // ||d(S V^T)||_F / ||S||, measured
    // The bound on the stored depths' alpha error: alpha_error + footprint_error, or more where
    // the extinction range needs a finer grid than 2^15 levels (k_s near 0 beside k_f > 0).
    double alpha_bound = 0.0;
    size_t detailed_pixels = 0;     // pixels that keep all their footprint rays
};

EncodedFrame encodeFrame(const BakeDescription& description, const FrameFactors& factors,
                         const FrameCodecSettings& settings);

// The resident form of a frame (resident_frame.h), its memory from `memory`; `table` is reused
// when the frame's depth grid is the same (else a new one is built). Reads payload versions 1
// to 3. Throws a Corrupt Error (naming `source` and the frame) when a payload does not match
// the description or is damaged.
ResidentFrame decodeResidentFrame(const BakeDescription& description, int frame, int rank,
                                  std::span<const std::byte> u, std::span<const std::byte> svt,
                                  std::span<const std::byte> depths, const std::string& source,
                                  std::pmr::memory_resource* memory, std::shared_ptr<const DepthTable> table);
// The same into an existing frame, reusing its buffers (and its depth_table when the grid is the
// same): a world that evicts one frame to load another decodes without fresh memory. On a throw
// the frame's contents are unspecified (but its buffers valid).
void decodeResidentFrame(const BakeDescription& description, int frame, int rank, std::span<const std::byte> u,
                         std::span<const std::byte> svt, std::span<const std::byte> depths, const std::string& source,
                         ResidentFrame& out);

// decodeResidentFrame one section at a time (what bench_frame_decode times apart): each sets the
// frame's shape (frame, pixels, columns, rank, rank_stride, samples) and the fields its section
// holds: w and u_scale; svt; depth_stride, mean_depth, detailed_pixels, detailed_depth and
// depth_table (reused when the grid is the same). The three in any order equal
// decodeResidentFrame, which calls them.
void decodeResidentU(const BakeDescription& description, int frame, int rank, std::span<const std::byte> u,
                     const std::string& source, ResidentFrame& out);
void decodeResidentSvt(const BakeDescription& description, int frame, int rank, std::span<const std::byte> svt,
                       const std::string& source, ResidentFrame& out);
void decodeResidentDepths(const BakeDescription& description, int frame, int rank, std::span<const std::byte> depths,
                          const std::string& source, ResidentFrame& out);

}  // namespace firelook::basis
