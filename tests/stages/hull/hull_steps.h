// The hull steps as the hull tests run them: carve the views, then find the exact
// crossings, with every crossing resolved.
#pragma once
#include <gtest/gtest.h>

#include <set>
#include <utility>

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

/// The set of grid lines along `axis` holding an occupied grid point: what an
/// axis-aligned orthographic view sees at the grid's resolution.
inline std::set<std::pair<int, int>> columns(const Volume& v, int axis) {
    std::set<std::pair<int, int>> s;
    auto grid = v.occupancy->deepCopy();
    grid->tree().voxelizeActiveTiles();
    for (auto it = grid->cbeginValueOn(); it; ++it) {
        const auto c = it.getCoord();
        s.insert({c[(axis + 1) % 3], c[(axis + 2) % 3]});
    }
    return s;
}

} // namespace cm::test
