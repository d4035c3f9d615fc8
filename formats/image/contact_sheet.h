// Contact sheets: several images tiled on a grid, for reviewing looks side by side.
#pragma once

#include <array>
#include <filesystem>
#include <span>

#include "image/image.h"
#include "image/image_io.h"

namespace firelook::image {

// Images fill rows left to right, top to bottom. Every cell has the size of the widest and of the
// tallest image; an image smaller than its cell is centred in it (offset rounded down). Cells are
// separated by gap_pixels of background (none around the border). The sheet has
// min(columns, images.size()) columns. background is premultiplied linear RGBA like any pixel.
// Throws ImageError when there are no images, columns < 1, gap_pixels < 0, or an image is malformed.
ImageRGBA makeContactSheet(std::span<const ImageRGBA> images, int columns, int gap_pixels,
                           const std::array<float, 4>& background = {0.0f, 0.0f, 0.0f, 0.0f});

struct ContactSheetOptions {
    int gap_pixels = 4;
    std::array<float, 4> background{0.0f, 0.0f, 0.0f, 0.0f};
    WriteOptions write;
};

// makeContactSheet, then writeImage.
void writeContactSheet(const std::filesystem::path& path, std::span<const ImageRGBA> images, int columns,
                       const ContactSheetOptions& options = {});

}  // namespace firelook::image
