// hull.plausible: see plausible.h. Steps: the hull's voxels are listed (tiles voxelized);
// per view they are binned into lines of sight in depth order (the tree's own columns along
// an axis, two counting sorts otherwise), which gives each voxel its run along the ray; the
// drawing's inflated profile on the same raster says how much of the run is plausible. A
// voxel's field value is its distance (cells, along the ray) outside that allowance, joined
// over the views by a smooth maximum, smoothed; where a line of sight would keep no voxel,
// the field is lowered by a smooth swelling until it keeps one; the volume keeps the voxels
// where the field is <= 0. The steps are Plausible's (plausible_state.h).
#include "plausible.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/error.h"
#include "geometry/hard_surface.h"
#include "plausible_loft.h"
#include "plausible_projection.h"
#include "plausible_state.h"

namespace cm {

void PlausibleOptions::declare(ParamBinder& b) {
    b.add(roundness, ParamSpec::Float("roundness", 1.0, 0.0, 1.0, "",
                                      "0: the visual hull as it is; 1: the full depth profile of the drawings"));
    b.add(profile_exponent,
          ParamSpec::Float("profile_exponent", 2.0, 1.0, 16.0, "",
                           "exponent n of the profile (1 - (1 - d/R)^n)^(1/n): 2 round, 1 a ridge, larger flatter"));
    b.add(ray_keep, ParamSpec::Int("ray_keep", 1, 1, 64, "cells",
                                   "occupied cells every line of sight keeps (1: one is enough for the "
                                   "silhouette; more keeps a minimum thickness)"));
    b.add(thin_cells, ParamSpec::Int("thin_cells", 3, 0, 64, "cells",
                                     "voxels in a run of at most this many cells along a view's line of sight, "
                                     "well inside a thin part of that view's drawing, are kept (fins, blades, "
                                     "ears seen face-on)"));
    b.add(view_blend, ParamSpec::Float("view_blend", 2.0, 0.0, 10.0, "cells",
                                       "the views' fields joined by a smooth maximum over this many cells "
                                       "(where one view objects mildly and the others do not, they win); 0: "
                                       "the plain maximum, any view removes"));
    b.add(smooth_cells, ParamSpec::Float("smooth", 2.5, 0.0, 8.0, "cells at 256",
                                         "standard deviation of the Gaussian smoothing of the field (a smoother "
                                         "new surface), in cells of a grid of 256 along the object's longest "
                                         "side, 0 for none"));
    b.add(loft, ParamSpec::Float("loft", 0.0, 0.0, 1.0, "",
                                 "share of the lofted cross-sections in the field (superellipses in the boxes the "
                                 "other views give, square where straight walls meet the view along them at its "
                                 "outline): 0 the drawings' depth profiles alone, 1 the lofted sections alone"));
    b.add(hard_surface,
          ParamSpec::Float("hard_surface", 0.0, 0.0, 1.0, "",
                           "weight of the hard-surface detection: where every axis view's outline runs mostly along "
                           "straight lines (a machined part), roundness and loft are scaled down by this times the "
                           "detected hardness, keeping the hull; 0 never"));
    b.add(ghost, ParamSpec::Float("ghost", 0.0, 0.0, 1.0, "",
                                  "weight of the hidden-depth prior: a part thin in one view whose depth the other "
                                  "views hide behind a wider part (an arm before the torso) gets a round section "
                                  "as deep as it is wide; 0 never"));
    b.add(handles, ParamSpec::Enum("handles", "keep", {"keep", "cut"},
                                   "keep: the kept volume keeps the hull's handles; cut: a handle no line of sight "
                                   "needs (two parts that touch in one view, like knees meeting in the front view, "
                                   "joined by the hull) is cut where it is thinnest, every drawn outline kept"));
}

void PlausibleStats::report(Metrics& m) const {
    m.count("hull_voxels", hull_voxels);
    m.count("candidates", candidates);
    m.count("removed_voxels", removed);
    m.metric("removed_pct", hull_voxels ? 100.0 * double(removed) / double(hull_voxels) : 0.0);
    m.count("kept_for_rays", kept_for_rays);
    m.count("thin_kept", thin_kept);
    m.count("new_crossings", new_crossings);
    m.count("thickened", thickened);
    m.count("short_rays", short_rays);
    m.count("thin_dropped", thin_dropped);
    m.count("loose_dropped", loose_dropped);
    m.count("cavities_filled", cavities_filled);
    m.count("pieces_joined", pieces_joined);
    m.count("far_dropped", far_dropped);
    m.count("genus_kept", genus_kept);
    m.count("handles", handles);
    m.count("handles_left", handles_left);
    m.count("handle_voxels", handle_voxels);
    m.count("ball_rays", ball_rays);
    m.count("square_voxels", square_voxels);
    m.count("ghost_voxels", ghost_voxels);
    m.count("unpaired_voxels", unpaired_voxels);
    m.metric("cell_px", cell_px);
    m.metric("hardness", hardness);
    m.metric("straight_pct", straight_pct);
    if (!step_seconds.empty()) {
        std::string json = "{";
        char buf[64];
        for (const auto& [name, seconds] : step_seconds) {
            std::snprintf(buf, sizeof buf, "%s\"%s\": %.4f", json.size() > 1 ? ", " : "", name.c_str(), seconds);
            json += buf;
        }
        m.metric_json("step_seconds", json + "}");
    }
    if (!refined) m.warn("the volume is not refined: the new surface gets crossings, the hull's own edges midpoints");
}

void PlausibleStats::step_done(const char* name) {
    const auto now = std::chrono::steady_clock::now();
    step_seconds.emplace_back(name, std::chrono::duration<double>(now - step_begin_).count());
    step_begin_ = now;
}

namespace plausible {

namespace {

openvdb::BoolGrid::Ptr voxelized_copy(const openvdb::BoolGrid& occupancy) {
    auto occ = occupancy.deepCopy();
    occ->tree().voxelizeActiveTiles(true);
    return occ;
}

} // namespace

// The field changes on fewer cells than the Gaussian smooths it over (its standard deviation
// is 2.5 cells at 256, 5 at 512): taken every sigma / 1.25 cells (2 at 256, 4 at 512, 8 at 1024)
// and interpolated trilinearly, the lattice step stays within two standard deviations, so the
// smoothed field moves little, for a few times fewer evaluations.
int field_stride(double sigma) { return std::clamp(int(std::lround(sigma / 1.25)), 1, 8); }

HullVoxels::HullVoxels(const openvdb::BoolGrid& occupancy)
    : occ(voxelized_copy(occupancy)), leaves(occ->tree()), nleaf(leaves.leafCount()), base(nleaf + 1, 0) {
    for (std::size_t l = 0; l < nleaf; ++l) base[l + 1] = base[l] + leaves.leaf(l).onVoxelCount();
    n = base[nleaf];
    if (n >= std::size_t(std::numeric_limits<std::uint32_t>::max()))
        throw Error("the hull has too many voxels (" + std::to_string(n) + ") for hull.plausible");
    occ->tree().evalActiveVoxelBoundingBox(box);
    maxdim = std::max({box.dim().x(), box.dim().y(), box.dim().z()});
}

Coord HullVoxels::coord_of(std::size_t i) const {
    const std::size_t l = std::size_t(std::upper_bound(base.begin(), base.end(), i) - base.begin()) - 1;
    const auto& mask = leaves.leaf(l).getValueMask();
    std::size_t r = i - base[l];
    for (openvdb::Index w = 0;; ++w) {
        std::uint64_t word = mask.getWord<std::uint64_t>(w);
        const std::size_t cnt = std::size_t(__builtin_popcountll(word));
        if (r >= cnt) {
            r -= cnt;
            continue;
        }
        for (; r > 0; --r) word &= word - 1; // drop the lowest set bits
        return leaves.leaf(l).offsetToGlobalCoord(openvdb::Index(w * 64 + unsigned(__builtin_ctzll(word))));
    }
}

Plausible::Plausible(const Volume& in, const Views& views, const PlausibleOptions& opt, PlausibleStats& st)
    : in_(in),
      views_(views),
      opt_(opt),
      st_(st),
      lat_(in.transform()),
      voxel_(in.voxel_size()),
      vox_(*in.occupancy),
      columns_(vox_.leaves, vox_.base),
      nv_(views.views.size()),
      blend_(float(opt.view_blend)),
      soft_(blend_ > 0),
      deep_(soft_ ? std::exp(-kClamp / blend_) : 0.0f) {
    st_.hull_voxels = vox_.n;
    // The field is smoothed afterwards (smooth()) over more cells than the trilinear
    // interpolation spans: it is taken every `stride` cells (every other one at 256, every
    // fourth at 512: an eighth and a 64th of the evaluations) and interpolated.
    const int stride = field_stride(opt_.smooth_cells * double(vox_.maxdim) / 256.0);
    if (stride > 1) coarse_ = std::make_unique<const CoarseLattice>(vox_.leaves, vox_.base, stride);
    // Written leaf by leaf side by side: each thread's first write maps its own pages (a fill
    // in one call would map all 4 + 1 bytes per voxel on one thread). The voxels whose field
    // is taken are marked on the way.
    phi_.resize(vox_.n);
    thin_.resize(vox_.n);
    const float phi0 = soft_ ? 0.0f : -std::numeric_limits<float>::infinity();
    const std::vector<LeafMask>* exact = coarse_ ? &coarse_->exact() : nullptr;
    tbb::parallel_for(std::size_t(0), vox_.nleaf, [&](std::size_t l) {
        const auto b = std::ptrdiff_t(vox_.base[l]), e = std::ptrdiff_t(vox_.base[l + 1]);
        std::fill(phi_.begin() + b, phi_.begin() + e, phi0);
        std::fill(thin_.begin() + b, thin_.begin() + e, std::uint8_t(0));
        if (exact) vox_.for_leaf(l, &(*exact)[l], [&](std::size_t i, openvdb::Index) { thin_[i] = kExact; });
    });
}

// The lofted prior blended in. A square section (where the hull is the section) keeps the
// lofted field, which leaves the hull there, whatever the share: the profiles would round a
// box's edges. It is taken where the views' fields are (fill_in() interpolates the blend).
void Plausible::loft() {
    const float share = float(opt_.loft);
    const bool coarse = coarse_ != nullptr;
    std::atomic<std::size_t> squares{0}, unpaired{0};
    loft_by_leaf(vox_, projections(), opt_.profile_exponent, coarse ? &coarse_->exact() : nullptr,
                 [&](const std::uint32_t* index, const LoftValue* lofted, std::size_t cnt) {
                     std::size_t sq = 0, un = 0;
                     for (std::size_t k = 0; k < cnt; ++k) {
                         const LoftValue& v = lofted[k];
                         // A section the view along its axis does not confirm (ghost volume
                         // between limbs) leaves the say to the profiles.
                         // A box the parts' tracks rule out (a ghost between two legs) is
                         // the prior's alone: the profiles would fill it.
                         const float own = std::max(v.drop, v.square + (1.0f - v.square) * share * v.fit);
                         float& phi = phi_[index[k]];
                         phi = own * v.field + (1.0f - own) * phi;
                         sq += v.square >= 0.5f;
                         un += v.drop > 0;
                         if (v.square >= 0.5f) thin_[index[k]] |= kSquare;
                     }
                     squares += sq;
                     unpaired += un;
                 });
    st_.square_voxels = squares;
    st_.unpaired_voxels = unpaired;
}

const std::array<Projection, 3>& Plausible::projections() {
    if (!proj_) proj_ = std::make_shared<const std::array<Projection, 3>>(project_hull(vox_));
    return *proj_;
}

void Plausible::fill_in() {
    proj_.reset();
    if (!coarse_) return;
    const bool lofted = opt_.loft > 0;
    coarse_->interpolate(phi_, lofted ? &thin_ : nullptr, kSquare);
    if (!lofted) return;
    std::atomic<std::size_t> squares{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vox_.n), [&](const tbb::blocked_range<std::size_t>& r) {
        std::size_t k = 0;
        for (std::size_t i = r.begin(); i != r.end(); ++i) k += (thin_[i] & kSquare) != 0;
        squares += k;
    });
    st_.square_voxels = squares;
}

void Plausible::remove() {
    // (thin_'s buffer, every value written: no new pages to clear.)
    removed_.swap(thin_);
    removed_.resize(vox_.n);
    thin_ = {};
    std::atomic<std::size_t> count{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vox_.n), [&](const tbb::blocked_range<std::size_t>& r) {
        std::size_t k = 0;
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            removed_[i] = cur_[i] > 0;
            k += removed_[i];
        }
        count += k;
    });
    st_.removed = count;
    st_.kept_for_rays = st_.candidates > st_.removed ? st_.candidates - st_.removed : 0;
    phi_ = {};
}

double Plausible::finest_cell_px() const {
    double finest = 1e300;
    for (const auto& R : rasters_) finest = std::min(finest, R.cp);
    return finest;
}

} // namespace plausible

Result<std::shared_ptr<Volume>, PlausibleStats> make_plausible(const Volume& in, std::shared_ptr<const Views> views,
                                                               const PlausibleOptions& given, Progress progress) {
    if (!in.occupancy) throw Error("the volume has no occupancy grid (connect hull.carve or its refinement)");
    if (!views) views = in.views;
    if (!views || views->views.empty()) throw Error("no views to keep the silhouettes of");
    PlausibleStats st;
    st.refined = in.crossings != nullptr;
    // 0. A machined part keeps its hull: the rounding scaled down by the detected hardness.
    PlausibleOptions opt = given;
    if (given.hard_surface > 0) {
        std::vector<double> shares;
        st.hardness = given.hard_surface * cm::hard_surface(*views, shares);
        st.straight_pct = 100.0 * *std::min_element(shares.begin(), shares.end());
        opt.roundness *= 1.0 - st.hardness;
        opt.loft *= 1.0 - st.hardness;
        opt.ghost *= 1.0 - st.hardness;
    }
    // 1. The hull's voxels.
    plausible::Plausible p(in, *views, opt, st);
    st.step_done("voxels");
    progress(0.05);
    // 2. Per view: lines of sight, runs along them in depth order, the profile, the field.
    const std::size_t nv = views->views.size();
    for (std::size_t v = 0; v < nv; ++v) {
        p.view_field(v);
        progress(0.05 + 0.4 * double(v + 1) / double(nv));
    }
    p.join_views();
    st.step_done("views");
    if (opt.loft > 0) p.loft();
    if (opt.ghost > 0) p.ghost();
    p.fill_in();
    st.step_done("priors");
    // 3. The field smoothed; thin parts kept.
    p.smooth();
    st.step_done("smooth");
    progress(0.55);
    // 4. Every line of sight keeps a voxel.
    p.cover_lines_of_sight();
    progress(0.65);
    // 5. Removal: the voxels where the field is above 0.
    p.remove();
    st.step_done("cover");
    progress(0.7);
    // 6-7. The output volume: occupancy and crossings (plausible_volume.cpp).
    std::shared_ptr<Volume> out =
        plausible_volume(in, p.voxels(), p.removed(), p.field(), p.rays(), opt.handles == "cut", st, progress);
    st.cell_px = p.finest_cell_px();
    progress(1.0);
    return {std::move(out), st};
}

} // namespace cm
