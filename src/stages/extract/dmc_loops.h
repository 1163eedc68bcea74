// The Marching Cubes loops as Dual Marching Cubes (dual_mc.cpp) reads them: each loop's
// crossings, the loops around each crossing in the order of its fan, and loops cut in
// pieces where two would share two edges.
//
// The dual of the loops is 2-manifold when no two loops share more than one edge. Two
// loops in neighbouring cells share two when their common face is ambiguous and each loop
// holds both of its segments (the face's inside corners joined on both sides, as where a
// part one cell thin crosses a face diagonally): their two vertices would be joined by two
// edges, one edge of four polygons. One of the two loops is then cut in two by a chord
// across the cell, each piece holding one segment, and gets a vertex per piece
// (split_shared_faces in dmc_loops.cpp).
#pragma once
#include <array>
#include <cstddef>
#include <vector>

#include "core/mesh.h"
#include "dmc_octree.h"
#include "marching_cubes.h"

namespace cm::dmc {

/// The triangles of the Marching Cubes mesh around each vertex (CSR), rotated so the
/// vertex comes first.
struct Fans {
    std::vector<Index> first;              ///< per vertex, into `tri`
    std::vector<std::array<Index, 3>> tri; ///< (triangle, next vertex, previous vertex)
};

/// A loop cut into pieces by chords: each piece a cycle of crossings in outward order.
struct SplitLoop {
    std::vector<Index> cycle;               ///< the whole loop
    std::vector<std::vector<Index>> pieces; ///< pieces[0] keeps the loop's index
    std::vector<Index> id;                  ///< each piece's loop index
};

/// The loops of the dual mesh (the Marching Cubes loops, some cut in pieces) and the rings of
/// loops around its crossings.
class DualLoops {
public:
    /// Fills D.loop_first and D.loop_cross (each loop's crossings) and D.loop_cell from the
    /// loops of `mc`, cutting the loops that would share two edges with a neighbour: the new
    /// pieces are loops from P.loop_cell.size() on. Keeps a reference to `P`.
    DualLoops(const Mesh& mc, const MarchingCubesPatches& P, DualMesh& D);
    /// The number of loops cut.
    std::size_t cut() const { return splits_.size(); }
    /// The loops around crossing v in the order of its fan (outward orientation), a cut loop's
    /// pieces in its place; returns their count, -1 when there are more than `cap` or the fan
    /// is not one cycle.
    int around(Index v, Index* out, int cap) const;

private:
    const MarchingCubesPatches& P_;
    Fans fans_;
    std::vector<SplitLoop> splits_;
    std::vector<int> split_of_; ///< per loop before the cut: its index in splits_ (-1: not cut)
    std::size_t uncut_;         ///< the loops before the cut
};

} // namespace cm::dmc
