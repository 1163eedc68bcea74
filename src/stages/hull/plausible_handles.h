// The handles of the kept volume that no line of sight needs, cut (hull.plausible with
// `handles: cut`).
//
// The visual hull has handles of its own where two parts touch in one view and no other view
// shows them apart: a camel's knees meet in the front view, so the hull joins its left and
// right legs there, a ring through the body per pair of legs; a man's hand on his hip closes
// the daylight between arm and body. The drawings cannot tell a touch from a join, and a
// modeller reads such a touch as two parts side by side. The genus repair (plausible_genus.h)
// keeps every handle the hull has; this step takes them out where the drawings allow it.
//
// The kept volume is grown again from its deepest voxel (the grid distance to the outside,
// deepest first, each depth in the order it is reached), adding a voxel only when it changes
// no topology (it is simple: the grown voxels about it one 26-connected piece, the others one
// 6-connected piece touching it) or joins grown pieces that are apart. A ring is closed last
// where it is thinnest, and the voxels that would close it stay out: a cut one voxel thick
// across the thinnest place of each handle. A cut that empties a line of sight of some view
// (the touch of the knees seen from the front) is moved: one of its voxels on that line is
// grown first, the next growth closes the ring elsewhere about it, so the cut steps around the
// line (up to four growths; what is still uncovered then gets its voxels back, its handle
// with them). Every line of sight keeps a voxel, so the silhouettes stay exact; no piece is cut
// off and no cavity sealed. A ring no cut can open without emptying a line of sight (a drawn
// ring: a handle, a torus seen through its hole) keeps its handle.
//
// A voxel whose grown neighbours are one piece is grown even where the outside about it is not
// (it closes a tunnel of the grown voxels, the last voxel of a hole through a plate): that only
// gives back what is kept. What a cut leaves joined to the rest of its part by an edge or a
// corner alone, which Marching Cubes would give a surface of its own, is cut with it where every
// line of sight keeps a voxel without it, else the cut about it is grown back. A large grid
// (over 320 cells) finds its cuts on a grid twice as coarse first and grows voxel by voxel only
// about them (the rest of the kept voxels grown at once): the growth's cost is in the voxels it
// visits one by one, and the skin of a thick body is most of them.
#pragma once
#include <cstddef>
#include <functional>
#include <vector>

#include <openvdb/openvdb.h>
#include <openvdb/tree/LeafManager.h>

#include "plausible_rays.h"

namespace cm::plausible {

/// What cut_handles() did.
struct HandleCut {
    long handles = 0;       ///< handles of the kept volume before (pieces - Euler characteristic)
    long handles_left = 0;  ///< and after
    std::size_t voxels = 0; ///< voxels taken out
    int growths = 0;        ///< growths run (0: no handle, or too large a box to grow in)
};

/// The Euler characteristic (V - E + F - C of the union of the closed voxel cubes) and the
/// 26-connected pieces of the on voxels of `tree`. With no cavity, handles = pieces - Euler.
struct VoxelTopology {
    long euler = 0, pieces = 0;
    long handles() const { return pieces - euler; }
};
VoxelTopology voxel_topology(const openvdb::BoolTree& tree);

/// Cuts the handles of the kept volume (`leaves`: the on voxels, every leaf voxelized) as
/// above; `rays` the views' lines of sight (every cell holding a kept voxel keeps one).
/// A cut reaching deeper than `most` cells from the outside (grid steps by faces) is no touch
/// but a drawn ring: it is not made. `taken(coord)` is told of every voxel taken out, before
/// the leaves are changed.
/// A box longer than `coarse_above` cells finds its cuts on a grid twice as coarse first (a
/// coarse voxel on where one of its eight is) and grows voxel by voxel only within `most` + 4
/// cells of them, the rest of the kept voxels grown at once.
HandleCut cut_handles(openvdb::tree::LeafManager<openvdb::BoolTree>& leaves, const std::vector<RayRaster>& rays,
                      int most, const std::function<void(const openvdb::Coord&)>& taken, int coarse_above = 320);

} // namespace cm::plausible
