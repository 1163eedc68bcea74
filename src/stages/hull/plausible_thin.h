// The hull's thin parts (edges between two outside grid points that pass through the hull,
// `thin_enter` / `thin_leave`, hull.marching_intersections) after hull.plausible's removal.
// Marching Cubes hangs a thin part on the surface of the cells around its edges; a chain of
// them (edges sharing a cell) hangs on the body where one of its cells has an inside corner.
// Where the removal took what a chain hung on, the chain would float free in the mesh: a
// crumb of a few faces a cell or less across, a piece of its own in Blender's outliner.
#pragma once
#include <cstddef>

#include "core/volume.h"

namespace cm::plausible {

/// Appends to `out.extra` the grids of `in.extra` with the thin-part grids replaced by the
/// thin parts that still hang on the output occupancy `now`: an edge goes where the removal
/// took a grid point around it (its ends' 26 neighbours), and a chain of edges that hung on
/// the hull's occupancy and hangs on nothing in `now` goes whole (a chain that hung on nothing
/// in the hull either, a wire apart from the rest, stays as the hull has it). Returns the
/// number of edges dropped.
std::size_t keep_hanging_thin_parts(const Volume& in, const openvdb::BoolGrid& now, Volume& out);

} // namespace cm::plausible
