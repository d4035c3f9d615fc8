// How much each light source's columns weigh when a frame's basis is compressed.
//
// A basis column is an image per unit of its source: emission per unit RBF coefficient, a
// directional light per unit irradiance. Their scales are unrelated (the axis derivation scales
// the emission stops with the data's density, a scene's light is in its own units), so an error
// bound relative to the whole basis lets one source vanish into the rounding of another: four
// voxels of density 1e6 made the emission columns 1e5 times the sun's, and the SVD and the S V^T
// grid dropped the sun's light entirely. The SVD (baker/bake/basis_compression.h) and the storage
// grids (frame_codec.h) therefore measure error on the basis with every source raised to within
// kMaxSourceRatio (in norm) of the largest: the emission columns (all bins together) and each
// light's columns are one source each. A source's relative error is then at most about
// kMaxSourceRatio times the bound, whatever a look mixes. The sources of real frames lie within
// 2-5 of each other (the bundled sample and samples/data/smoke at 64x64) and are stored as before;
// raising them to equal norms cost 13-19% more bytes on the smoke frames with no change in a
// sun-only look's image (mean and RMS against the reference equal to 5 digits).
#pragma once

#include <span>
#include <vector>

namespace firelook::basis {

inline constexpr double kMaxSourceRatio = 10.0;

// energy[c]: the sum of squares of every column of kind c (c < bins: emission bin c; then one per
// light), over the grid points. Returns the factor for each kind: what raises its source's norm to
// 1 / kMaxSourceRatio of the largest source's, and 1 for a source already there or with no energy
// (no source is scaled down).
std::vector<double> sourceBalance(std::span<const double> energy, int bins);

// sourceBalance of a frame's stored S V^T (`rank` values per column, column = point *
// columns_per_point + c): a column's energy in B is the energy of its S V^T values, U's columns
// being orthonormal. Values that are not finite count as 0 (the storage grids store them as 0).
std::vector<double> svtSourceBalance(std::span<const float> svt, int rank, int columns_per_point, int bins);

}  // namespace firelook::basis
