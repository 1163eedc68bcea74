// The state of one make_plausible() (plausible.h) and its named steps, along the numbered
// phases of the algorithm: 1 the hull's voxels (plausible.cpp); 2 each view's lines of sight,
// the profile of its drawing and its field, joined over the views, and 3 the field smoothed
// (plausible_profiles.cpp); 4 every line of sight keeps a voxel (plausible_cover.cpp); 5 the
// removal (plausible.cpp); 6-7 the output volume (plausible_volume.cpp).
#pragma once
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include <openvdb/openvdb.h>
#include <openvdb/tree/LeafManager.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "plausible.h"
#include "plausible_coarse.h"
#include "plausible_fields.h"
#include "plausible_rays.h"

namespace cm::plausible {

/// Smooth step from 0 at a to 1 at b (3t^2 - 2t^3), clamped.
inline double smoothstep(double x, double a, double b) {
    const double t = std::clamp((x - a) / (b - a), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

/// The lattice step (cells) the field is taken on before it is smoothed by a Gaussian of
/// standard deviation `sigma` cells (1: every voxel).
int field_stride(double sigma);

using BoolTree = openvdb::BoolTree;
using LeafT = BoolTree::LeafNodeType;

/// 1. The hull's voxels: a copy of the input's occupancy with its tiles voxelized, and the
/// voxels numbered leaf by leaf (voxel index = leaf base + rank of the on voxel, LeafManager
/// order), which every per-voxel array of the steps follows.
struct HullVoxels {
    openvdb::BoolGrid::Ptr occ;
    openvdb::tree::LeafManager<BoolTree> leaves;
    std::size_t nleaf = 0;
    std::vector<std::size_t> base; ///< nleaf + 1 entries: base[nleaf] is the voxel count
    std::size_t n = 0;
    openvdb::CoordBBox box; ///< of the voxels
    int maxdim = 0;         ///< the box's longest side, in cells

    /// @throw cm::Error when the hull has too many voxels to number in 32 bits.
    explicit HullVoxels(const openvdb::BoolGrid& occupancy);
    /// The grid point of voxel i.
    Coord coord_of(std::size_t i) const;
    /// body(i, offset in the leaf) for the voxels of leaf l in order; with `only`, just those in it.
    template <typename Body>
    void for_leaf(std::size_t l, const LeafMask* only, Body&& body) const {
        const auto& mask = leaves.leaf(l).getValueMask();
        std::size_t i = base[l];
        for (openvdb::Index w = 0; w < 8; ++w) {
            const std::uint64_t all = mask.getWord<std::uint64_t>(w);
            // A voxel's index counts the word's voxels before it.
            for (std::uint64_t word = only ? all & (*only)[w] : all; word; word &= word - 1) {
                const int b = __builtin_ctzll(word);
                body(i + std::size_t(__builtin_popcountll(all & ((std::uint64_t(1) << b) - 1))),
                     w * 64 + openvdb::Index(b));
            }
            i += std::size_t(__builtin_popcountll(all));
        }
    }
    /// body(i, coord) for every voxel, in parallel over leaves.
    template <typename Body>
    void for_voxels(Body&& body) const {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nleaf), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t l = r.begin(); l != r.end(); ++l) {
                std::size_t i = base[l];
                for (auto it = leaves.leaf(l).cbeginValueOn(); it; ++it) body(i++, it.getCoord());
            }
        });
    }
};

struct Projection;

/// A voxel of a line of sight: the line's cell, the voxel's index and its grid point.
struct Vox {
    std::uint32_t cell, i;
    Coord c;
};

/// Steps 2 to 5 over the hull's voxels: the field of each voxel (cells outside the views'
/// allowance, joined over the views and smoothed), lowered where a line of sight would keep
/// no voxel, and the voxels it removes.
class Plausible {
public:
    /// Step 1 (the voxels); `views` must outlive this.
    Plausible(const Volume& in, const Views& views, const PlausibleOptions& opt, PlausibleStats& st);

    /// 2. View v: its lines of sight, the profile of its drawing on them and its share of the
    /// field. Views in order, then join_views().
    void view_field(std::size_t v);
    /// 2. The views' shares joined (the smooth maximum's logarithm).
    void join_views();
    /// 2, with the lofted prior in place of the views' profiles (plausible_loft.h).
    void loft();
    /// 2. Hidden depth: thin parts whose depth a wider part hides get a round section
    /// (plausible_ghost.h).
    void ghost();
    /// 2. The hull's projections along the grid axes, which the lofted and hidden-depth priors
    /// share (plausible_projection.h): made at the first call, let go by fill_in().
    const std::array<Projection, 3>& projections();
    /// 2. The field between the lattice points where it was taken (plausible_coarse.h);
    /// nothing where every voxel is taken (grids under about 200 cells).
    void fill_in();
    /// 3. The field smoothed over the hull's voxels; thin parts keep their voxels.
    void smooth();
    /// 4. Every line of sight keeps min(ray_keep, its voxels) voxels with field <= 0.
    void cover_lines_of_sight();
    /// 5. The voxels the field removes (field > 0).
    void remove();

    HullVoxels& voxels() { return vox_; }
    UninitVector<std::uint8_t>& removed() { return removed_; }
    /// The field after step 4 (the one the removal and the new crossings follow).
    const UninitVector<float>& field() const { return cur_; }
    /// The finest line-of-sight raster pitch, pixels of its view.
    double finest_cell_px() const;
    /// Each view's lines of sight.
    const std::vector<RayRaster>& rays() const { return rasters_; }

private:
    /// A view's drawing on its lines of sight: distance to the outline and local inscribed
    /// radius, cells.
    struct Profile {
        std::vector<float> dist, radius;
    };
    // 2, one view.
    std::vector<std::uint32_t> lay_out_rays(std::size_t v, std::vector<std::uint32_t>& key);
    Profile profile_of(std::size_t v, const std::vector<std::uint32_t>& count) const;
    void score_view(std::size_t v, const Profile& p, const std::vector<std::uint32_t>& key);
    void score_line(const Profile& p, double gap, std::uint32_t c, const std::uint32_t* idx, const double* dep,
                    std::size_t cnt);
    // 3.
    void keep_thin();
    // 4, its parts (a) to (d) and what they share.
    void find_short_lines();
    /// With `low`: the values of view v's list (lists_[v]) entry by entry, else cur_'s.
    bool shortfall(std::size_t v, std::size_t g, float* t, const float* low = nullptr) const;
    std::vector<Vox> kept_voxels_of(std::size_t v, const std::vector<char>& want) const;
    void swell();
    void mark_swollen(const SwellField& field);
    void lower_lists(const SwellField& field, const std::vector<std::vector<char>>& covered);
    void drop_loose();
    std::size_t lower_members(std::size_t l, const LeafColumns::Mask& member, const LeafColumns::Mask& joined);
    void reach_with_balls();
    void balls_for_view(std::size_t v, BallField& balls, double coarse);
    bool short_lines_of(std::size_t v, std::vector<char>& flag, std::vector<std::size_t>& short_groups) const;
    void add_balls(std::size_t v, const std::vector<std::size_t>& short_groups, const std::vector<std::uint32_t>& near,
                   BallField& balls, double coarse) const;
    void blend_balls(const BallField& balls);
    void keep_best();

    /// body(cell, voxel indices in depth order, count, coord(k)) for every line of sight of
    /// view v that holds a voxel, in parallel: the grid's columns for a view along an axis,
    /// else the voxels sorted by cell and depth. coord(k) is the grid point of voxel k.
    /// With `skip` (per leaf: voxels whose lines of sight are not wanted), axis views leave
    /// out the columns holding one of them (the body is still asked about every other view's).
    template <typename Body>
    void for_rays(std::size_t v, Body&& body, const std::vector<LeafColumns::Mask>* skip = nullptr) const;
    /// The same for the lines of sight of view v with `want[cell]` set alone: axis views deal
    /// no other column.
    template <typename Body>
    void for_rays_in(std::size_t v, const std::vector<char>& want, Body&& body) const;

    // Cells of field below 0 a needed voxel gets, and over which a ball blends into the field.
    static constexpr float kMargin = 0.75f;
    static constexpr float kBlend = 1.5f;
    // The views' values are clamped at 20 cells (far enough for any decision) to stay in range.
    static constexpr float kClamp = 20.0f;
    // Bits of thin_: in a short run of a thin part; the field is taken there, not interpolated
    // (every voxel on small grids); the voxel's lofted section is square.
    static constexpr std::uint8_t kThin = 1, kExact = 2, kSquare = 4;

    const Volume& in_;
    const Views& views_;
    const PlausibleOptions& opt_;
    PlausibleStats& st_;
    const Lattice lat_;
    const double voxel_;
    HullVoxels vox_;
    const LeafColumns columns_;
    const std::size_t nv_;
    // The views' join: a smooth maximum over `blend_` cells (soft_), else the plain maximum;
    // deep_ is the value of a voxel deep inside a view's allowance.
    const float blend_;
    const bool soft_;
    const float deep_;
    // phi_: how far (cells, along the ray) a voxel lies outside the views' allowance; thin_:
    // in a short run of a thin part of some drawing; cur_: phi_ lowered (step 4: it takes
    // phi_'s buffer).
    UninitVector<float> phi_, cur_;
    UninitVector<std::uint8_t> thin_;
    std::shared_ptr<const std::array<Projection, 3>> proj_;
    // The lattice the field is taken on (null: every voxel, on small grids).
    std::unique_ptr<const CoarseLattice> coarse_;
    std::vector<RayRaster> rasters_;
    // Per view, its voxels by line of sight (cell c: order[start[c]] .. order[start[c + 1]]).
    std::vector<std::vector<std::uint32_t>> orders_, starts_;
    std::vector<std::vector<std::uint32_t>> ray_total_; // per view, voxels per line of sight (axis views: 0 or 1)
    // Step 4: voxels every line of sight keeps; per view, the voxels of its short lines of
    // sight by line (lists_[v]) and where each line starts there (groups_[v]).
    std::uint32_t keep_ = 1;
    std::vector<std::vector<Vox>> lists_;
    std::vector<std::vector<std::size_t>> groups_;
    UninitVector<std::uint8_t> removed_;
    // Step 4 (a): the swelling, which only rises from round to round, so a voxel's lowered
    // value is its value less the swelling's last rise at it. cur_ keeps the values before it
    // until drop_loose() lowers the field once; the rounds read the lowered values of the
    // short lines' voxels (low_[v], entry by entry of lists_[v]). swollen_: per leaf, whether
    // a round raised the swelling about it.
    std::unique_ptr<SwellField> swelling_;
    std::vector<char> swollen_;
    std::vector<std::vector<float>> low_;
    // Step 4: per leaf, the voxels the field kept before the swelling.
    std::vector<LeafColumns::Mask> kept_;
};

// A body of for_rays() as the columns of an axis view are dealt (LeafColumns): the column's
// cell, and the grid point of its k-th voxel from its first and its coordinates along the axis.
template <typename Body>
auto column_rays(const RayRaster& R, Body& body) {
    return [&R, &body](const Coord& first, const std::uint32_t* idx, const int* along, std::size_t cnt) {
        body(R.cell(first), idx, cnt, [&](std::size_t k) {
            Coord c = first;
            c[R.axis] = along[k];
            return c;
        });
    };
}

template <typename Body>
void Plausible::for_rays(std::size_t v, Body&& body, const std::vector<LeafColumns::Mask>* skip) const {
    const RayRaster& R = rasters_[v];
    if (R.axis_aligned) {
        columns_.for_columns(R.axis, skip, column_rays(R, body));
        return;
    }
    const auto& order = orders_[v];
    const auto& start = starts_[v];
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, start.size() - 1, 256),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t c = r.begin(); c != r.end(); ++c)
                              if (start[c + 1] > start[c]) {
                                  const std::uint32_t* idx = order.data() + start[c];
                                  body(std::uint32_t(c), idx, std::size_t(start[c + 1] - start[c]),
                                       [&](std::size_t k) { return vox_.coord_of(idx[k]); });
                              }
                      });
}

template <typename Body>
void Plausible::for_rays_in(std::size_t v, const std::vector<char>& want, Body&& body) const {
    const RayRaster& R = rasters_[v];
    if (R.axis_aligned) {
        columns_.for_columns_where(
            R.axis, [&](const Coord& c) { return want[R.cell(c)] != 0; }, column_rays(R, body));
        return;
    }
    for_rays(v, [&](std::uint32_t c, const std::uint32_t* idx, std::size_t cnt, auto&& coord) {
        if (want[c]) body(c, idx, cnt, coord);
    });
}

/// Steps 6 and 7: the output volume from the voxels `removed` (changed: pockets put back, the
/// handles cut taken out) and the field `field`; changes `vox` (the output's occupancy); with
/// `cut_handles`, the handles no line of sight of `rays` needs are cut (plausible_handles.h);
/// fills the removal's figures of `st` (plausible_volume.cpp).
std::shared_ptr<Volume> plausible_volume(const Volume& in, HullVoxels& vox, UninitVector<std::uint8_t>& removed,
                                         const UninitVector<float>& field, const std::vector<RayRaster>& rays,
                                         bool cut_handles, PlausibleStats& st, const Progress& progress);

} // namespace cm::plausible
