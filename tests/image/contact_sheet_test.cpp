#include "image/contact_sheet.h"

#include <gtest/gtest.h>

#include <vector>

#include "../support/temp_dir.h"

namespace firelook::image {
namespace {

// Image k is filled with the value k + 1 in every channel, so a sheet pixel tells which image it came from.
ImageRGBA labelledImage(int width, int height, int k) {
    ImageRGBA image(width, height);
    for (float& value : image.pixels) value = static_cast<float>(k + 1);
    return image;
}

TEST(ContactSheet, PlacesEachImageInItsCell) {
    // Sizes differ: cells take the widest (6) and tallest (5); five images in three columns -> two rows.
    const std::vector<ImageRGBA> images = {labelledImage(6, 4, 0), labelledImage(2, 5, 1),
                                           labelledImage(4, 3, 2), labelledImage(6, 5, 3),
                                           labelledImage(1, 1, 4)};
    const int gap = 2;
    const std::array<float, 4> background = {0.25f, 0.5f, 0.75f, 1.0f};
    const ImageRGBA sheet = makeContactSheet(images, 3, gap, background);
    ASSERT_EQ(sheet.width, 3 * 6 + 2 * gap);
    ASSERT_EQ(sheet.height, 2 * 5 + 1 * gap);

    for (int k = 0; k < static_cast<int>(images.size()); ++k) {
        const ImageRGBA& image = images[static_cast<std::size_t>(k)];
        const int cell_left = (k % 3) * (6 + gap);
        const int cell_top = (k / 3) * (5 + gap);
        const int left = cell_left + (6 - image.width) / 2;
        const int top = cell_top + (5 - image.height) / 2;
        for (int y = cell_top; y < cell_top + 5; ++y) {
            for (int x = cell_left; x < cell_left + 6; ++x) {
                const bool inside = x >= left && x < left + image.width && y >= top && y < top + image.height;
                for (int c = 0; c < 4; ++c) {
                    const float expected = inside ? static_cast<float>(k + 1) : background[c];
                    ASSERT_EQ(sheet.at(x, y)[c], expected)
                        << "image " << k << " at (" << x << ", " << y << ")";
                }
            }
        }
    }
    // A gap column between the first two cells, and the empty sixth cell, hold the background.
    EXPECT_EQ(sheet.at(6, 0)[0], background[0]);
    EXPECT_EQ(sheet.at(7, 3)[1], background[1]);
    EXPECT_EQ(sheet.at(2 * (6 + gap) + 3, 5 + gap + 2)[2], background[2]);
}

TEST(ContactSheet, FewerImagesThanColumnsMakesOneRowOfThem) {
    const std::vector<ImageRGBA> images = {labelledImage(3, 2, 0), labelledImage(3, 2, 1)};
    const ImageRGBA sheet = makeContactSheet(images, 8, 1);
    EXPECT_EQ(sheet.width, 2 * 3 + 1);
    EXPECT_EQ(sheet.height, 2);
    EXPECT_EQ(sheet.at(4, 1)[0], 2.0f);
}

TEST(ContactSheet, RefusesBadArguments) {
    const std::vector<ImageRGBA> images = {labelledImage(2, 2, 0)};
    EXPECT_THROW(makeContactSheet({}, 2, 0), ImageError);
    EXPECT_THROW(makeContactSheet(images, 0, 0), ImageError);
    EXPECT_THROW(makeContactSheet(images, 1, -1), ImageError);
    std::vector<ImageRGBA> malformed = images;
    malformed[0].pixels.pop_back();
    EXPECT_THROW(makeContactSheet(malformed, 1, 0), ImageError);
}

TEST(ContactSheet, WritesAReadableFile) {
    testing::TempDir dir;
    const std::vector<ImageRGBA> images = {labelledImage(2, 2, 0), labelledImage(2, 2, 1),
                                           labelledImage(2, 2, 2)};
    ContactSheetOptions options;
    options.gap_pixels = 1;
    writeContactSheet(dir.path() / "sheet.exr", images, 2, options);
    const ImageRGBA read = readImage(dir.path() / "sheet.exr");
    EXPECT_EQ(read.width, 5);
    EXPECT_EQ(read.height, 5);
    EXPECT_EQ(read.at(0, 3)[0], 3.0f);  // third image starts the second row; small integers are exact in half
}

}  // namespace
}  // namespace firelook::image
