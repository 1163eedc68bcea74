// The steps of hull.plausible (plausible.cpp) that are not its algorithm: each view's lines
// of sight laid out as a raster at the grid's pitch, and the filters over rasters and grids
// that smooth the profiles and the scores.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <openvdb/openvdb.h>

#include "core/views.h"

namespace cm::plausible {

using openvdb::Coord;

// A view's lines of sight at the grid's pitch: cell (i, j) of the raster covers
// [x0 + i cp, x0 + (i + 1) cp) x [y0 + j cp, ...) in pixels; a voxel belongs to the cell
// its centre projects into; depth is along the view direction (orthographic) or the
// distance from the camera centre (perspective).
struct RayRaster {
    const Camera* cam = nullptr;
    double cp = 1, x0 = 0, y0 = 0;
    int w = 0, h = 0;
    Vec3d centre;
    double gap = 0; ///< a depth step larger than this splits a run

    std::uint32_t cell(const Vec3d& p) const {
        const Vec2d q = cam->project(p);
        const int i = std::clamp(int(std::floor((q.x - x0) / cp)), 0, w - 1);
        const int j = std::clamp(int(std::floor((q.y - y0) / cp)), 0, h - 1);
        return std::uint32_t(j) * std::uint32_t(w) + std::uint32_t(i);
    }
    float depth(const Vec3d& p) const {
        if (cam->orthographic()) return float(dot(p, cam->d));
        return float(length(p - centre));
    }
};

/// The world position of grid point c.
Vec3d world_of(const openvdb::math::Transform& xf, const Coord& c);
/// The view's raster over the grid's box, `voxel` world units a cell; throws cm::Error when it
/// cannot be laid out (a camera inside the box, or too many cells).
RayRaster make_raster(const View& view, const openvdb::math::Transform& xf, const openvdb::CoordBBox& box,
                      double voxel);
/// 3x3 box passes over a w x h raster, normalised over the cells not `masked`; masked cells
/// keep their value.
void box_blur(std::vector<float>& f, const std::vector<char>* masked, int w, int h, int passes);
/// 3x3 max passes over a w x h raster.
void dilate(std::vector<float>& f, int w, int h, int passes);
/// One binomial smoothing pass of `src` into `dst` (plausible.cpp smooths the scores with it).
void binomial_pass(const openvdb::FloatGrid& src, openvdb::FloatGrid& dst);

} // namespace cm::plausible
