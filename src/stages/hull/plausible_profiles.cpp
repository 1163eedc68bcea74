// Steps 2 and 3 of hull.plausible (plausible_state.h): each view's lines of sight, the
// inflated depth profile of its drawing on them and its share of the field, the views' shares
// joined, and the field smoothed.
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "geometry/hull_distance.h"
#include "plausible_state.h"

namespace cm {

double profile_fraction(double u, double exponent, double roundness) {
    u = std::clamp(u, 0.0, 1.0);
    const double f = std::pow(std::max(0.0, 1.0 - std::pow(1.0 - u, exponent)), 1.0 / exponent);
    return 1.0 - roundness * (1.0 - f);
}

std::vector<float> local_inscribed_radius(const std::vector<float>& dist, int w, int h) {
    struct Disc {
        int x, y;
        float r;
    };
    // A cell's disc lies inside a neighbour's when the neighbour is farther from the
    // outline by their distance: only the others (the medial ridge) paint. A distance
    // grows by at least cos 22.5 deg of a step towards the neighbour nearest its gradient,
    // so 0.9 of a step keeps the ridge thin at the cost of a tenth of a cell of radius.
    // (The ridge is found row by row side by side.)
    std::vector<std::vector<Disc>> ridge(std::size_t(std::max(h, 0)));
    tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y != rows.end(); ++y)
            for (int x = 0; x < w; ++x) {
                const float r = dist[std::size_t(y) * w + x];
                if (r <= 0) continue;
                bool covered = false;
                for (int dy = -1; dy <= 1 && !covered; ++dy)
                    for (int dx = -1; dx <= 1 && !covered; ++dx) {
                        const int nx = x + dx, ny = y + dy;
                        if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
                        const float step = (dx != 0 && dy != 0) ? 1.41421356f : 1.0f;
                        covered = dist[std::size_t(ny) * w + nx] >= r + 0.9f * step;
                    }
                if (!covered) ridge[std::size_t(y)].push_back({x, y, r});
            }
    });
    // Each block of rows paints the discs that reach it (|row - y| < r). A row's cell takes the
    // largest radius of the spans over it: the spans are painted largest first, each cell
    // once, the painted ones skipped (the next unpainted cell at or after each, path-halved).
    std::vector<Disc> discs;
    for (const auto& row : ridge) discs.insert(discs.end(), row.begin(), row.end());
    std::vector<float> out(dist.size(), 0.0f);
    struct Span {
        float r;
        int x0, x1;
    };
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 16), [&](const tbb::blocked_range<int>& rows) {
        std::vector<Disc> near;
        for (const Disc& d : discs)
            if (float(d.y) - d.r < float(rows.end()) && float(d.y) + d.r > float(rows.begin() - 1)) near.push_back(d);
        std::vector<Span> spans;
        std::vector<int> next(std::size_t(w) + 1);
        const auto unpainted = [&](int x) {
            while (next[std::size_t(x)] != x) x = next[std::size_t(x)] = next[std::size_t(next[std::size_t(x)])];
            return x;
        };
        for (int y = rows.begin(); y != rows.end(); ++y) {
            float* row = out.data() + std::size_t(y) * w;
            spans.clear();
            for (const Disc& d : near) {
                const float dy = float(y - d.y);
                if (std::abs(dy) >= d.r) continue;
                const float half = std::sqrt(d.r * d.r - dy * dy);
                const int x0 = std::max(0, int(std::ceil(float(d.x) - half)));
                const int x1 = std::min(w - 1, int(std::floor(float(d.x) + half)));
                if (x0 <= x1) spans.push_back({d.r, x0, x1});
            }
            std::sort(spans.begin(), spans.end(), [](const Span& a, const Span& b) { return a.r > b.r; });
            for (int x = 0; x <= w; ++x) next[std::size_t(x)] = x;
            for (const Span& sp : spans)
                for (int x = unpainted(sp.x0); x <= sp.x1; x = unpainted(x + 1)) {
                    row[x] = sp.r;
                    next[std::size_t(x)] = x + 1;
                }
            for (int x = 0; x < w; ++x) row[x] = std::max(row[x], dist[std::size_t(y) * w + x]);
        }
    });
    return out;
}

} // namespace cm

namespace cm::plausible {

namespace {

// A short run well inside the drawing is a thin part seen face-on (an ear, a fin); near the
// outline short runs are the rim of any body.
bool thin_cell(float dist, float radius, int thin_cells) { return dist >= 1.5f && radius <= 2.0f * float(thin_cells); }

} // namespace

void Plausible::view_field(std::size_t v) {
    std::vector<std::uint32_t> key;
    std::vector<std::uint32_t> count = lay_out_rays(v, key);
    const Profile profile = profile_of(v, count);
    score_view(v, profile, key);
    ray_total_.push_back(std::move(count));
}

// The view's raster, and each line of sight's voxels in depth order (increasing or, along a
// negative axis, decreasing: the runs are the same), with their depth keys in `key`; returns
// the voxels per line of sight (for a view along an axis, 1 for a line that holds any).
std::vector<std::uint32_t> Plausible::lay_out_rays(std::size_t v, std::vector<std::uint32_t>& key) {
    rasters_.push_back(make_raster(views_.views[v], lat_, vox_.box, voxel_));
    const RayRaster& R = rasters_.back();
    const std::size_t ncell = std::size_t(R.w) * std::size_t(R.h);
    std::vector<std::uint32_t> count(ncell, 0);
    orders_.emplace_back();
    starts_.emplace_back();
    if (R.axis_aligned) {
        // Only whether a line of sight holds a voxel is asked of an axis view's count.
        columns_.for_column_points(R.axis, [&](const Coord& c) { count[R.cell(c)] = 1; });
        return count;
    }
    std::vector<std::uint32_t> cell(vox_.n), by_depth;
    key.resize(vox_.n);
    vox_.for_voxels([&](std::size_t i, const Coord& c) {
        cell[i] = R.cell(c);
        key[i] = R.depth_key(c);
    });
    stable_bucket_order(key, R.dkeys, {}, by_depth);
    stable_bucket_order(cell, std::uint32_t(ncell), by_depth, orders_[v], &starts_[v]);
    for (std::size_t c = 0; c < ncell; ++c) count[c] = starts_[v][c + 1] - starts_[v][c];
    return count;
}

// The drawing as these lines of sight see it (a cell is inside when a voxel of the hull
// projects into it), its distance to the outline and local inscribed radius. The distance is
// the drawing's own (sub-pixel), in cells; cells the hull reaches although their centre is
// outside the drawing get 0.
Plausible::Profile Plausible::profile_of(std::size_t v, const std::vector<std::uint32_t>& count) const {
    const View& view = views_.views[v];
    const RayRaster& R = rasters_[v];
    const std::size_t ncell = std::size_t(R.w) * std::size_t(R.h);
    const SilhouetteSdf sdf = silhouette_sdf(view.coverage, view.name);
    std::vector<char> outside(ncell, 0);
    Profile p;
    p.dist.assign(ncell, 0.0f);
    tbb::parallel_for(tbb::blocked_range<int>(0, R.h), [&](const tbb::blocked_range<int>& rows) {
        for (int j = rows.begin(); j != rows.end(); ++j)
            for (int i = 0; i < R.w; ++i) {
                const std::size_t c = std::size_t(j) * std::size_t(R.w) + std::size_t(i);
                if (count[c] == 0) {
                    outside[c] = 1;
                    continue;
                }
                const double px = R.x0 + (i + 0.5) * R.cp, py = R.y0 + (j + 0.5) * R.cp;
                p.dist[c] = float(std::max(0.0, -sdf.sample(px, py) / R.cp));
            }
    });
    // The local inscribed radius steps where one disc takes over from another; blurred
    // over the drawing, the profile (and the surface) has no creases there.
    p.radius = local_inscribed_radius(p.dist, R.w, R.h);
    box_blur(p.radius, &outside, R.w, R.h, 4);
    for (std::size_t c = 0; c < ncell; ++c) p.radius[c] = std::max(p.radius[c], p.dist[c]);
    return p;
}

// The view's share of the field, line of sight by line of sight.
void Plausible::score_view(std::size_t v, const Profile& p, const std::vector<std::uint32_t>& key) {
    const RayRaster& R = rasters_[v];
    const double gap = R.gap_keys * R.dq / voxel_;
    tbb::enumerable_thread_specific<std::vector<double>> depths;
    if (R.axis_aligned) {
        auto line = [&](const Coord& first, const std::uint32_t* idx, const int* along, std::size_t cnt) {
            auto& dep = depths.local();
            dep.assign(along, along + cnt);
            score_line(p, gap, R.cell(first), idx, dep.data(), cnt);
        };
        if (!coarse_) {
            columns_.for_columns(R.axis, line);
            return;
        }
        // Where the field is taken on a lattice, a line of sight has work only where it holds a
        // voxel whose value is taken, or crosses a thin part of the drawing (whose short runs
        // are marked): the others (three in four at 256, 15 in 16 at 512) are not dealt.
        columns_.for_columns_wanted(
            R.axis, coarse_->exact(),
            [&](const Coord& c) {
                const std::uint32_t cell = R.cell(c);
                return thin_cell(p.dist[cell], p.radius[cell], opt_.thin_cells);
            },
            line);
        return;
    }
    for_rays(v, [&](std::uint32_t c, const std::uint32_t* idx, std::size_t cnt, auto&&) {
        auto& dep = depths.local();
        dep.resize(cnt);
        for (std::size_t k = 0; k < cnt; ++k) dep[k] = R.depth_of_key(key[idx[k]]) / voxel_;
        score_line(p, gap, c, idx, dep.data(), cnt);
    });
}

// The field of line of sight c: `dep` the depths (cells) of its voxels `idx`, runs split where
// they step by more than `gap` cells.
void Plausible::score_line(const Profile& p, double gap, std::uint32_t c, const std::uint32_t* idx, const double* dep,
                           std::size_t cnt) {
    const bool soft = soft_, coarse = coarse_ != nullptr;
    const float blend = blend_, deep = deep_;
    const double frac =
        profile_fraction(p.radius[c] > 0 ? p.dist[c] / p.radius[c] : 0.0, opt_.profile_exponent, opt_.roundness);
    // The inflated cross-section's own half-depth (radius R), so a round drawing is a
    // round solid even where the run is long.
    const double inflated = frac * double(p.radius[c]);
    const bool thin_part = thin_cell(p.dist[c], p.radius[c], opt_.thin_cells);
    for (std::size_t rb = 0; rb != cnt;) {
        std::size_t re = rb + 1;
        while (re != cnt && std::abs(dep[re] - dep[re - 1]) <= gap) ++re;
        const double front = std::min(dep[rb], dep[re - 1]) - 0.5, back = std::max(dep[rb], dep[re - 1]) + 0.5;
        const double half = 0.5 * (back - front), mid = 0.5 * (back + front);
        // Allowed half-depth: the larger of the profile's share of the run and the
        // inflated cross-section (within the run).
        const double allow = std::max(frac * half, std::min(half, inflated));
        const bool is_thin = thin_part && re - rb <= std::size_t(opt_.thin_cells);
        for (std::size_t k = rb; k != re; ++k) {
            std::uint8_t& flags = thin_[idx[k]];
            if (is_thin) flags |= kThin;
            // Between the lattice points of a finer grid the field is interpolated (fill_in()).
            if (coarse && !(flags & kExact)) continue;
            const float sv = float(std::abs(dep[k] - mid) - allow);
            // (Deep inside the allowance, the common case, the clamped value's exponential
            // is a constant.)
            if (soft) phi_[idx[k]] += sv <= -kClamp ? deep : std::exp(std::clamp(sv, -kClamp, kClamp) / blend);
            else phi_[idx[k]] = std::max(phi_[idx[k]], sv);
        }
        rb = re;
    }
}

// The views are joined by a smooth maximum (log-sum-exp over `blend` cells, less the log of
// the count): where they agree it is their value, where one view objects mildly and the
// others do not, the others win, so fewer lines of sight are left to swell to.
void Plausible::join_views() {
    if (!soft_) return;
    // Deep inside every view's allowance (the sum of the constants, added in the same
    // order) the value is a constant too.
    const float blend = blend_;
    float all_deep = 0.0f;
    for (std::size_t v = 0; v < nv_; ++v) all_deep += deep_;
    const float deep_value = blend * std::log(all_deep / float(nv_));
    // Where the field is taken on a lattice, only the voxels whose value is taken are visited.
    const std::vector<LeafMask>* exact = coarse_ ? &coarse_->exact() : nullptr;
    tbb::parallel_for(std::size_t(0), vox_.nleaf, [&](std::size_t l) {
        vox_.for_leaf(l, exact ? &(*exact)[l] : nullptr, [&](std::size_t i, openvdb::Index) {
            phi_[i] = phi_[i] == all_deep ? deep_value : blend * std::log(phi_[i] / float(nv_));
        });
    });
}

// The field smoothed over the hull's voxels (a normalised Gaussian, so the outside does not
// pull it), giving a smooth zero level for the new surface. The smoothing is given in cells of
// a grid of 256 along the object's longest side, so the surface is as smooth at any
// resolution; voxels farther from the zero level than four standard deviations keep their
// values (their side of it is not in doubt).
void Plausible::smooth() {
    const double sigma = opt_.smooth_cells * double(vox_.maxdim) / 256.0;
    smooth_field(phi_, vox_.leaves, vox_.base, vox_.box, sigma, float(4.0 * sigma + 2.0));
    keep_thin();
}

// Thin parts have no volume to spare.
void Plausible::keep_thin() {
    std::atomic<std::size_t> kept{0}, cand{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vox_.n), [&](const tbb::blocked_range<std::size_t>& r) {
        std::size_t k = 0, c = 0;
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            if (!(phi_[i] > 0)) continue;
            if (thin_[i] & kThin) {
                ++k;
                phi_[i] = -0.5f;
            } else {
                ++c;
            }
        }
        kept += k;
        cand += c;
    });
    st_.thin_kept = kept;
    st_.candidates = cand;
}

} // namespace cm::plausible
