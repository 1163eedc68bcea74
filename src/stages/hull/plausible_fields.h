// The fields of hull.plausible beside the voxels' own: the filters over rasters and grids
// that smooth the profiles and the field, the swelling that lowers the field about the lines
// of sight it must keep, and the union of balls by which the volume swells to the lines of
// sight it must cover.
#pragma once
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include <openvdb/openvdb.h>
#include <openvdb/tree/LeafManager.h>

#include "util/uninit_vector.h"

namespace cm::plausible {

using openvdb::Coord;

/// 3x3 box passes over a w x h raster, normalised over the cells not `masked`; masked cells
/// keep their value.
void box_blur(std::vector<float>& f, const std::vector<char>* masked, int w, int h, int passes);

/// Smooths `value` (one per voxel of `leaves`, numbered leaf base + rank) by a Gaussian of
/// standard deviation `sigma` grid cells, normalised over the voxels (the outside does not
/// pull it): the voxels' means on a dense lattice of `f` cells a cell (f a power of 2 up to
/// sigma), binomial passes there, and back trilinearly. Voxels whose value lies farther than
/// `reach` from 0 keep theirs.
void smooth_field(UninitVector<float>& value, const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves,
                  const std::vector<std::size_t>& base, const openvdb::CoordBBox& box, double sigma, float reach);

// A smooth, non-negative field on a coarse dense lattice (`f` grid cells a coarse cell) over a
// box of the grid: how far the field is lowered about the lines of sight it must still cover.
// Seeds raise it to their value in a ball of their value's radius (plus two coarse cells),
// then it is smoothed; sampled trilinearly at grid points.
class SwellField {
public:
    SwellField(const openvdb::CoordBBox& box, int f);
    /// Raises the field to at least `value` (grid cells) about grid point c.
    void seed(const Coord& c, float value);
    /// Adds the seeds since the last call to the field, smoothed (two binomial passes).
    void settle();
    /// Trilinear value at grid point c (0 outside the box).
    float at(const Coord& c) const;
    /// The same values for the grid points of the 8^3 block at `origin`, with the per-axis
    /// lattice positions worked out once: at(x, y, z) for local coordinates 0..7.
    class Block {
    public:
        Block(const SwellField& f, const Coord& origin);
        float at(int x, int y, int z) const;

    private:
        const SwellField& f_;
        int c0_[3][8];   ///< lower lattice index per axis and local coordinate (-1: outside)
        double t_[3][8]; ///< the upper one's weight
    };
    /// Whether the last settle() raised the field anywhere about the grid points of `b`.
    bool raised_in(const openvdb::CoordBBox& b) const;

private:
    // A box of lattice cells, bounds included (empty: x0 > x1).
    struct Box {
        int x0, x1, y0, y1, z0, z1;
    };
    /// body(first cell, count) for the rows along z of box b, in parallel.
    template <typename Body>
    void for_box(const Box& b, Body&& body) const;

    // A grid point's lattice cell along an axis and the weight of the next cell.
    struct Step {
        int i;
        double t;
    };

    Coord lo_;
    int f_, nx_, ny_, nz_;
    // Per axis, the Step of the grid points lo_ + 0, 1, ... that have a cell above theirs.
    std::array<std::vector<Step>, 3> steps_;
    // g_: the field; last_: the last settle()'s rise, 0 outside box_; tmp_: its scratch.
    std::vector<float> g_, last_, tmp_;
    Box box_{0, -1, 0, -1, 0, -1};
    std::vector<std::pair<std::uint32_t, float>> seeds_; // coarse cell, value
    bool any_ = false;
};

// The signed distance (grid cells, negative inside) to a union of balls, kept on a coarse
// dense lattice (`f` grid cells a coarse cell) over a box of the grid and sampled
// trilinearly: the swellings by which the volume reaches the lines of sight it must cover.
class BallField {
public:
    BallField(const openvdb::CoordBBox& box, int f);
    /// A ball of `radius` grid cells about `centre` (index space).
    void add(const openvdb::Vec3d& centre, double radius) { balls_.push_back({centre, radius}); }
    /// Writes the balls added since the last call into the lattice, within `reach` cells of
    /// their surface (farther, the field is left at +infinity).
    void settle(double reach);
    bool empty() const { return !any_; }
    /// Trilinear value at grid point c (+infinity where any corner is beyond reach).
    float at(const Coord& c) const;
    /// Whether the field is finite anywhere about the grid points of `b`.
    bool any_in(const openvdb::CoordBBox& b) const;

private:
    struct Ball {
        openvdb::Vec3d centre;
        double radius;
    };
    Coord lo_;
    int f_, nx_, ny_, nz_;
    std::vector<float> g_;
    std::vector<Ball> balls_;
    bool any_ = false;
};

} // namespace cm::plausible
