// The hull steps as the hull tests run them: carve the views, then find the exact
// crossings, with every crossing resolved.
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "carve.h"
#include "refine.h"
#include "render/raster.h"

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

/// A mesh's binary mask seen by `c`, framed as `conceptmesh render-views` frames its views:
/// the box's centre at the image centre, 0.9 of the image across the box's largest extent.
inline View mask_view(const Mesh& m, const std::string& name, Camera c, int size, Vec3d lo, Vec3d hi) {
    const Vec3d mid = (lo + hi) * 0.5, ext = hi - lo;
    c.scale = 0.9 * size / std::max({ext[0], ext[1], ext[2]});
    c.cx = size / 2.0 - c.scale * dot(mid, c.r);
    c.cy = size / 2.0 + c.scale * dot(mid, c.u);
    View v;
    v.name = name;
    v.camera = c;
    v.width = v.height = size;
    const std::vector<std::uint8_t> mask = render_mask(m, c, size, size);
    v.coverage = Coverage(std::vector<float>(mask.begin(), mask.end()), size, size);
    return v;
}

/// The box of a mesh's vertices.
inline std::pair<Vec3d, Vec3d> box_of(const Mesh& m) {
    Vec3d lo(1e300, 1e300, 1e300), hi(-1e300, -1e300, -1e300);
    for (const auto& p : m.positions)
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], double(p[a])), hi[a] = std::max(hi[a], double(p[a]));
    return {lo, hi};
}

} // namespace cm::test
