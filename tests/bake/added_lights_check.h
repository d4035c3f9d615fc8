// The check both relighting light sets (six-way, sphere) share: lights added after a model's own
// columns change nothing else.
#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "bake/basis_tracer.h"
#include "bake_test_support.h"

namespace firelook::bake::test {

// Photon paths and camera rays are drawn independently of the columns, and the orders' stopping
// test ignores the added lights' columns: `with_lights` (plain and `added` lights after its columns)
// traces every column of `plain` and the optical depths to the same bytes. Every added light lights
// the box: a column of zeros would mean a light that misses it. name(l) names added light l.
inline void expectAddedLightsLeaveEveryOtherColumn(const render::Medium& medium, const render::Camera& camera,
                                                   const BasisModel& plain, const BasisModel& with_lights,
                                                   int added, const std::function<std::string(int)>& name) {
    const FrameBasis a = traceFrameBasis(medium, camera, plain, fastTrace());
    const FrameBasis b = traceFrameBasis(medium, camera, with_lights, fastTrace());
    ASSERT_EQ(a.scattering_orders, b.scattering_orders);
    const int pixels = a.width * a.height;
    for (int p = 0; p < pixels; ++p)
        for (int c = 0; c < plain.columnsPerPoint(); ++c)
            ASSERT_EQ(basisValue(a, plain, p, 0, c), basisValue(b, with_lights, p, 0, c))
                << "pixel " << p << " column " << c;
    EXPECT_EQ(a.depth_b, b.depth_b);
    for (int l = 0; l < added; ++l) {
        double sum = 0.0;
        for (int p = 0; p < pixels; ++p) sum += basisValue(b, with_lights, p, 0, plain.columnsPerPoint() + l);
        EXPECT_GT(sum, 0.0) << name(l) << " misses the box";
    }
}

}  // namespace firelook::bake::test
