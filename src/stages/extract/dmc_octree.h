// The dual mesh of extract.dual_marching_cubes before it is triangulated, its QEF, and
// the adaptive step: cells merged up an octree where one vertex represents them.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include <openvdb/openvdb.h>

#include "core/vec.h"

namespace cm {

using Index = std::uint32_t;
constexpr Index kNoIndex = std::numeric_limits<Index>::max();

/// Quadratic error of a point against tangent planes: sum_i (n_i . (x - p_i))^2.
struct Qef {
    double A[6] = {0, 0, 0, 0, 0, 0}; ///< xx, xy, xz, yy, yz, zz of sum n n^T
    Vec3d b{};                        ///< sum n (n . p)
    double c = 0;                     ///< sum (n . p)^2
    Vec3d sum{};                      ///< sum p (the mass point is sum / count)
    int count = 0;
    void add(const Vec3d& p, const Vec3f& n);
    void add(const Qef& o);
    double error(const Vec3d& x) const;
    /// The minimum (truncated pseudo-inverse about the mass point, eigenvalues under
    /// `singular_ratio` of the largest dropped) inside the box lo + [0, size]^3: a minimum
    /// outside drops the weakest remaining direction until it is inside (rank 0: the mass
    /// point), and is clamped only if even that is not.
    struct Result {
        Vec3d x;
        int rank = 0;
        bool clamped = false;
    };
    Result solve(const Vec3d& lo, double size, double singular_ratio) const;
};

/// Everything in index space (one unit = one cell).
struct DualMesh {
    std::vector<Vec3d> cross_pos;              ///< per crossing (Marching Cubes vertex)
    std::vector<Vec3f> cross_n;                ///< its outward normal (zero: not a crossing)
    std::vector<Index> loop_first, loop_cross; ///< per loop: its crossings (CSR)
    std::vector<openvdb::Coord> loop_cell;     ///< per loop: its cell
    std::vector<Vec3d> vert;                   ///< per loop: its vertex
    /// Per crossing: the loops around it, outward order (CSR); empty for centre vertices.
    std::vector<Index> face_first, face_loops;
};

struct AdaptiveStats {
    std::size_t merged = 0; ///< loops whose vertex was merged into another
    int levels = 0;         ///< octree levels that merged anything
};

/// @brief Merges the loops' vertices up the octree of cells (2^L cells a side at level L):
/// a node whose children each hold one vertex becomes one vertex when the QEF minimum of
/// all its crossings, clamped to the node, lies within `max_error` cells of every
/// crossing's tangent plane, the surface it holds is one disc (the contraction leaves the
/// mesh closed, 2-manifold and of the same topology: the new vertex's ring is one simple
/// cycle) and no polygon around it turns over. On return rep[l] is the loop whose vertex
/// (D.vert[rep[l]]) stands for loop l.
/// Loops with `frozen[l]` set (when given) keep their own vertex, and so does every loop of
/// an octree node that holds one of them.
void merge_octree(DualMesh& D, double max_error, double singular_ratio, std::vector<Index>& rep, AdaptiveStats& st,
                  const std::vector<char>* frozen = nullptr);

} // namespace cm
