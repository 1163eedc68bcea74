// Plausible volume inside the visual hull with the silhouettes kept exact
// (hull.plausible).
//
// Every shape whose projections are the silhouettes lies inside the visual hull, and a
// silhouette pixel needs only one occupied point along its line of sight. So each view
// allows, along each of its lines of sight, a share of the hull's run there given by an
// inflated depth profile of its drawing; a voxel's field value is how far it lies outside
// that allowance (cells, a smooth maximum over the views), smoothed, and the volume keeps the voxels
// where it is <= 0. Where that would leave a line of sight empty, the field is lowered by a
// smooth swelling of the volume until the line keeps a voxel: the silhouettes stay those of
// the hull by construction. The new surface lies on the field's zero level; every crossing
// on a silhouette cone is kept as hull.marching_intersections found it.
#pragma once
#include <chrono>
#include <cstddef>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/algorithm.h"
#include "core/volume.h"

namespace cm {

/// The parameters of hull.plausible.
struct PlausibleOptions {
    /// 0: the visual hull as it is; 1: the full depth profile of the drawings.
    double roundness;
    /// Exponent n of the profile (1 - (1 - d/R)^n)^(1/n): 2 is a round (circular)
    /// cross-section, 1 a ridge, larger values flatter and boxier.
    double profile_exponent;
    /// Occupied cells every line of sight keeps (1: the silhouettes only need one).
    int ray_keep;
    /// A voxel in a run of at most this many cells along a view's line of sight, where that
    /// view's drawing is thin (inscribed radius at most twice this) and the cell lies at
    /// least 1.5 cells inside it, is kept: thin parts (fins, blades, ears) seen face-on have
    /// no volume to spare. (Short runs at a drawing's outline are any body's rim.)
    int thin_cells;
    /// How the views' fields are joined: a smooth maximum over this many cells (log-sum-exp
    /// less the log of the number of views), 0 for the plain maximum (any view removes).
    double view_blend;
    /// Standard deviation of the Gaussian smoothing of the field, in cells of a grid of 256
    /// along the object's longest side (scaled with the resolution, so the new surface is
    /// as smooth at any resolution), 0 for none (the parameter `smooth`).
    double smooth_cells;
    /// Share of the lofted prior in the field (plausible_loft.h): 0 the drawings' depth
    /// profiles alone, 1 the lofted cross-sections alone. Where a lofted section is square
    /// (straight walls, and the view along them shows the box's sides), it has the whole say.
    double loft;
    /// Weight of the hard-surface detection (geometry/hard_surface.h): when every axis view's outline
    /// runs mostly along straight lines (a machined part), the rounding and the lofted prior are
    /// scaled down by this times the detected hardness, so the hull stays; 0 never.
    double hard_surface;
    /// Weight of the hidden-depth prior (plausible_ghost.h): a part thin in one view whose depth
    /// the other views hide behind a wider part gets a round section as deep as it is wide;
    /// 0 never.
    double ghost;
    /// "keep": the kept volume keeps the hull's handles (plausible_genus.h); "cut": the handles
    /// no line of sight needs are cut where they are thinnest (plausible_handles.h).
    std::string handles;

    PlausibleOptions() { set_declared_defaults(*this); }
    /// Every parameter.
    void declare(ParamBinder& b);
};

struct PlausibleStats {
    std::size_t hull_voxels = 0;     ///< occupied grid points of the input
    std::size_t candidates = 0;      ///< voxels outside the profiles (field > 0), not thin
    std::size_t removed = 0;         ///< voxels taken out
    std::size_t kept_for_rays = 0;   ///< candidates kept by the swelling that covers the lines of sight
    std::size_t thin_kept = 0;       ///< voxels outside the profiles kept as thin parts
    std::size_t new_crossings = 0;   ///< crossings placed on the field's zero level
    std::size_t thickened = 0;       ///< removed voxels put back so no plate is one voxel thin
    std::size_t thin_dropped = 0;    ///< thin-part edges of the input dropped (their hull removed)
    std::size_t short_rays = 0;      ///< lines of sight the profiles left short (swollen to)
    std::size_t loose_dropped = 0;   ///< swollen voxels dropped as apart from the rest
    std::size_t pieces_joined = 0;   ///< pieces of the kept volume joined to the body by a bridge
    std::size_t far_dropped = 0;     ///< voxels of crumbs far from the body dropped (plausible_pieces.h)
    std::size_t cavities_filled = 0; ///< removed voxels put back as sealed inside the kept volume
    std::size_t genus_kept = 0;      ///< removed voxels put back as opening a tunnel (plausible_genus.h)
    std::size_t handles = 0;         ///< handles of the kept volume before the cut (handles: cut)
    std::size_t handles_left = 0;    ///< and after it
    std::size_t handle_voxels = 0;   ///< voxels taken out by the cut (plausible_handles.h)
    std::size_t ball_rays = 0;       ///< lines of sight then covered by a ball about the volume
    std::size_t square_voxels = 0;   ///< voxels whose lofted section is square (the hull kept; loft > 0)
    std::size_t ghost_voxels = 0;    ///< voxels outside a hidden part's round section (ghost > 0)
    std::size_t unpaired_voxels = 0; ///< voxels in boxes pairing two parts' runs (loft > 0; plausible_tracks.h)
    double cell_px = 0;              ///< line-of-sight raster pitch, pixels of the finest view
    double hardness = 0;             ///< detected hard-surface weight in [0, 1] (hard_surface > 0)
    double straight_pct = 0;         ///< the least straight view's share of straight outline, %
    bool refined = false;            ///< the input had crossings (hull.marching_intersections)
    /// Wall seconds of the stage's steps, in order (the run report's `step_seconds`).
    std::vector<std::pair<std::string, double>> step_seconds;
    /// The counts, the share removed, the pitch and the steps' seconds; a warning when the
    /// input was not refined.
    void report(Metrics& m) const;
    /// Ends step `name`, begun where the last one ended (the first: when the stats were made,
    /// at the stage's start).
    void step_done(const char* name);

private:
    std::chrono::steady_clock::time_point step_begin_ = std::chrono::steady_clock::now();
};

/// @brief The plausible volume of the (carved, optionally refined) hull `in` and `views`.
/// The output's occupancy is a subset of the input's; every line-of-sight cell of every
/// view (a raster at the grid's pitch on the view's image plane, a voxel belonging to
/// the cell its centre projects into) that holds an input voxel still holds one. The
/// input's exact crossings are kept wherever an edge still runs from an inside point to
/// a point outside the hull; edges into the removed region get the field's zero crossing.
/// Orthographic and perspective views; TBB-parallel over leaves, columns and cells. `views`
/// null: the volume's own. The result carries the input's views and silhouette tables.
/// @param progress reported between steps; cm::Cancelled from it stops the work.
/// @throw cm::Error when the volume has no occupancy, no views are given, or a view's
///        line-of-sight raster would be unreasonably large (a camera inside the object).
Result<std::shared_ptr<Volume>, PlausibleStats> make_plausible(const Volume& in, std::shared_ptr<const Views> views,
                                                               const PlausibleOptions& opt, Progress progress = {});

/// The depth-profile fraction (1 - (1 - u)^n)^(1/n) at u = d / R in [0, 1], blended with
/// 1 by `roundness` (0 gives 1 everywhere: the hull).
double profile_fraction(double u, double exponent, double roundness);

/// @brief Local inscribed radius of a binary raster: for every inside cell, the radius
/// of the largest disc inside the shape that holds it ("local thickness"), with `dist`
/// the distance of every cell to the outline (cells). Cells outside get 0.
std::vector<float> local_inscribed_radius(const std::vector<float>& dist, int w, int h);

} // namespace cm
