#include "image/contact_sheet.h"

#include <algorithm>
#include <cstddef>
#include <string>

namespace firelook::image {

ImageRGBA makeContactSheet(std::span<const ImageRGBA> images, int columns, int gap_pixels,
                           const std::array<float, 4>& background) {
    if (images.empty()) throw ImageError("contact sheet: no images");
    if (columns < 1)
        throw ImageError("contact sheet: columns must be at least 1, not " + std::to_string(columns));
    if (gap_pixels < 0) throw ImageError("contact sheet: negative gap " + std::to_string(gap_pixels));

    int cell_width = 0;
    int cell_height = 0;
    for (std::size_t k = 0; k < images.size(); ++k) {
        const ImageRGBA& image = images[k];
        if (image.width < 0 || image.height < 0 ||
            image.pixels.size() !=
                4 * static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height)) {
            throw ImageError("contact sheet: image " + std::to_string(k) + " is malformed (" +
                             std::to_string(image.width) + "x" + std::to_string(image.height) + " with " +
                             std::to_string(image.pixels.size()) + " values)");
        }
        cell_width = std::max(cell_width, image.width);
        cell_height = std::max(cell_height, image.height);
    }
    const int count = static_cast<int>(images.size());
    const int used_columns = std::min(columns, count);
    const int rows = (count + used_columns - 1) / used_columns;

    ImageRGBA sheet(used_columns * cell_width + (used_columns - 1) * gap_pixels,
                    rows * cell_height + (rows - 1) * gap_pixels);
    for (std::size_t i = 0; i < sheet.pixels.size(); ++i) sheet.pixels[i] = background[i % 4];

    for (int k = 0; k < count; ++k) {
        const ImageRGBA& image = images[static_cast<std::size_t>(k)];
        if (image.width == 0) continue;  // nothing to place, and no row to address
        const int left = (k % used_columns) * (cell_width + gap_pixels) + (cell_width - image.width) / 2;
        const int top = (k / used_columns) * (cell_height + gap_pixels) + (cell_height - image.height) / 2;
        for (int y = 0; y < image.height; ++y) {
            const auto row_begin = image.pixels.begin() + 4 * static_cast<std::ptrdiff_t>(y) * image.width;
            std::copy(row_begin, row_begin + 4 * static_cast<std::ptrdiff_t>(image.width),
                      sheet.at(left, top + y).begin());
        }
    }
    return sheet;
}

void writeContactSheet(const std::filesystem::path& path, std::span<const ImageRGBA> images, int columns,
                       const ContactSheetOptions& options) {
    writeImage(path, makeContactSheet(images, columns, options.gap_pixels, options.background),
               options.write);
}

}  // namespace firelook::image
