// Volumes built from a signed distance function, for the extractor tests.
#pragma once
#include <functional>

#include "core/volume.h"

namespace cm::test {

using Sdf = std::function<double(const Vec3d&)>;

/// A volume on the lattice origin + h * ijk over `box`: inside where sdf < 0, crossings
/// found by bisection on each edge with differing ends (from the start point, as the
/// contract says), solid interior pruned into tiles.
Volume volume_from_sdf(const Sdf& sdf, const openvdb::CoordBBox& box, double h, Vec3d origin, bool refine = true);

/// Adds the normal grids "normal_x/y/z" of volume.h's crossings (as hull.marching_intersections
/// stores them) from the gradient of `sdf` at each crossing.
void add_sdf_normals(Volume& v, const Sdf& sdf);

} // namespace cm::test
