// The hull steps as the hull tests run them: carve the views, then find the exact
// crossings, with every crossing resolved.
#pragma once
#include <gtest/gtest.h>

#include "carve.h"
#include "refine.h"

namespace cm::test {

/// The refined hull of `views` at `resolution` cells; expects no unresolved crossing.
inline std::shared_ptr<const Volume> carve_and_refine(const std::shared_ptr<const Views>& views, int resolution) {
    CarveOptions opt;
    opt.resolution = resolution;
    const auto vol = carve(views, opt).value;
    const auto refined = refine(*vol, nullptr, {});
    const auto& ref = refined.value;
    const RefineStats& st = refined.stats;
    EXPECT_EQ(st.unresolved, 0u);
    return ref;
}

} // namespace cm::test
