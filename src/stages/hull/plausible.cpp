// hull.plausible: see plausible.h. Steps: the hull's voxels are listed (tiles voxelized);
// per view they are binned into line-of-sight cells and sorted by depth, which gives each
// voxel its place in its run along the ray; the drawing's inflated profile on the same
// raster says how much of the run is plausible; the score (worst over views) is smoothed
// and voxels are removed in decreasing score while every ray keeps `ray_keep` voxels.
#include "plausible.h"

#include "plausible_steps.h"

#include <openvdb/tools/Filter.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tree/LeafManager.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "geometry/hull_distance.h"
#include "geometry/silhouette_field.h"

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
    std::vector<Disc> ridge;
    for (int y = 0; y < h; ++y)
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
            if (!covered) ridge.push_back({x, y, r});
        }
    std::vector<float> out(dist.size(), 0.0f);
    tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y != rows.end(); ++y) {
            float* row = out.data() + std::size_t(y) * w;
            for (const Disc& d : ridge) {
                const float dy = float(y - d.y);
                if (std::abs(dy) >= d.r) continue;
                const float half = std::sqrt(d.r * d.r - dy * dy);
                const int x0 = std::max(0, int(std::ceil(float(d.x) - half)));
                const int x1 = std::min(w - 1, int(std::floor(float(d.x) + half)));
                for (int x = x0; x <= x1; ++x) row[x] = std::max(row[x], d.r);
            }
            for (int x = 0; x < w; ++x) row[x] = std::max(row[x], dist[std::size_t(y) * w + x]);
        }
    });
    return out;
}

namespace {

using openvdb::Coord;
using namespace plausible;
using BoolTree = openvdb::BoolTree;
using LeafT = BoolTree::LeafNodeType;

} // namespace

std::shared_ptr<Volume> make_plausible(const Volume& in, std::shared_ptr<const Views> views,
                                       const PlausibleOptions& opt, const std::function<void(double)>& progress,
                                       PlausibleStats* stats) {
    if (!in.occupancy) throw Error("the volume has no occupancy grid (connect hull.carve or its refinement)");
    if (!views) views = in.views;
    if (!views || views->views.empty()) throw Error("no views to keep the silhouettes of");
    auto step = [&](double f) {
        if (progress) progress(f);
    };
    PlausibleStats st;
    const auto& xf = in.transform();
    const double voxel = in.voxel_size();

    // 1. The hull's voxels, tiles voxelized; index = leaf base + rank of the on voxel.
    auto occ = in.occupancy->deepCopy();
    occ->tree().voxelizeActiveTiles(true);
    openvdb::tree::LeafManager<BoolTree> leaves(occ->tree());
    const std::size_t nleaf = leaves.leafCount();
    std::vector<std::size_t> base(nleaf + 1, 0);
    for (std::size_t l = 0; l < nleaf; ++l) base[l + 1] = base[l] + leaves.leaf(l).onVoxelCount();
    const std::size_t n = base[nleaf];
    st.hull_voxels = n;
    if (n >= std::size_t(std::numeric_limits<std::uint32_t>::max()))
        throw Error("the hull has too many voxels (" + std::to_string(n) + ") for hull.plausible");
    std::vector<Coord> coord(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nleaf), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t l = r.begin(); l != r.end(); ++l) {
            std::size_t i = base[l];
            for (auto it = leaves.leaf(l).cbeginValueOn(); it; ++it) coord[i++] = it.getCoord();
        }
    });
    openvdb::CoordBBox box;
    occ->tree().evalActiveVoxelBoundingBox(box);
    step(0.05);

    // 2. Per view: lines of sight, runs along them, the profile, the score.
    std::vector<float> score(n, -std::numeric_limits<float>::infinity());
    std::vector<float> total(n, 0.0f); // sum over views: orders the candidates within a tie
    std::vector<std::uint8_t> thin(n, 0);
    std::vector<RayRaster> rasters;
    std::vector<std::vector<std::uint32_t>> ray_count, ray_start, ray_order;
    const std::size_t nv = views->views.size();
    for (std::size_t v = 0; v < nv; ++v) {
        const RayRaster R = make_raster(views->views[v], xf, box, voxel);
        const std::size_t ncell = std::size_t(R.w) * std::size_t(R.h);
        std::vector<std::uint32_t> cell(n);
        std::vector<float> depth(n);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) {
                const Vec3d p = world_of(xf, coord[i]);
                cell[i] = R.cell(p);
                depth[i] = R.depth(p);
            }
        });
        std::vector<std::uint32_t> start(ncell + 1, 0);
        for (std::size_t i = 0; i < n; ++i) ++start[cell[i] + 1];
        for (std::size_t c = 0; c < ncell; ++c) start[c + 1] += start[c];
        std::vector<std::uint32_t> order(n), fill(start.begin(), start.end() - 1);
        for (std::size_t i = 0; i < n; ++i) order[fill[cell[i]]++] = std::uint32_t(i);
        fill = {};

        // The drawing as these lines of sight see it (a cell is inside when a voxel of the
        // hull projects into it), its distance to the outline and local inscribed radius.
        std::vector<std::uint32_t> count(ncell);
        std::vector<char> outside(ncell);
        for (std::size_t c = 0; c < ncell; ++c) {
            count[c] = start[c + 1] - start[c];
            outside[c] = count[c] == 0;
        }
        // Distance to the outline from the drawing itself (sub-pixel), in cells; cells the
        // hull reaches although their centre is outside the drawing get 0.
        const View& view = views->views[v];
        const SilhouetteSdf sdf = silhouette_sdf(view.coverage, view.width, view.height, view.name);
        std::vector<float> dist(ncell, 0.0f);
        tbb::parallel_for(tbb::blocked_range<int>(0, R.h), [&](const tbb::blocked_range<int>& rows) {
            for (int j = rows.begin(); j != rows.end(); ++j)
                for (int i = 0; i < R.w; ++i) {
                    const std::size_t c = std::size_t(j) * std::size_t(R.w) + std::size_t(i);
                    if (outside[c]) continue;
                    const double px = R.x0 + (i + 0.5) * R.cp, py = R.y0 + (j + 0.5) * R.cp;
                    dist[c] = float(std::max(0.0, -sdf.sample(px, py) / R.cp));
                }
        });
        // The local inscribed radius steps where one disc takes over from another; blurred
        // over the drawing, the profile (and the surface) has no creases there.
        std::vector<float> radius = local_inscribed_radius(dist, R.w, R.h);
        box_blur(radius, &outside, R.w, R.h, 4);
        for (std::size_t c = 0; c < ncell; ++c) radius[c] = std::max(radius[c], dist[c]);

        tbb::parallel_for(
            tbb::blocked_range<std::size_t>(0, ncell, 256), [&](const tbb::blocked_range<std::size_t>& r) {
                for (std::size_t c = r.begin(); c != r.end(); ++c) {
                    if (count[c] == 0) continue;
                    auto* b = order.data() + start[c];
                    auto* e = order.data() + start[c + 1];
                    std::sort(b, e, [&](std::uint32_t a, std::uint32_t q) { return depth[a] < depth[q]; });
                    const double frac = profile_fraction(radius[c] > 0 ? dist[c] / radius[c] : 0.0,
                                                         opt.profile_exponent, opt.roundness);
                    // The inflated cross-section's own half-depth (radius R in world units), so a
                    // round drawing is a round solid even where the run is short.
                    const double inflated = frac * double(radius[c]) * voxel;
                    for (auto* rb = b; rb != e;) {
                        auto* re = rb + 1;
                        while (re != e && double(depth[*re]) - double(depth[*(re - 1)]) <= R.gap) ++re;
                        const double front = double(depth[*rb]) - 0.5 * voxel,
                                     back = double(depth[*(re - 1)]) + 0.5 * voxel;
                        const bool is_thin = re - rb <= opt.thin_cells;
                        // Allowed half-depth: the larger of the profile's share of the run and the
                        // inflated cross-section (within the run).
                        const double half = 0.5 * (back - front);
                        const double allow = std::max(frac, std::min(1.0, inflated / half));
                        for (auto* it = rb; it != re; ++it) {
                            const double a = double(depth[*it]) - front, z = back - double(depth[*it]);
                            const double off = std::abs(a - z) / std::max(a + z, 1e-30);
                            const float sv = float(off - allow);
                            score[*it] = std::max(score[*it], sv);
                            total[*it] += sv;
                            if (is_thin) thin[*it] = 1;
                        }
                        rb = re;
                    }
                }
            });
        ray_count.push_back(std::move(count));
        ray_start.push_back(std::move(start));
        ray_order.push_back(std::move(order));
        rasters.push_back(R);
        step(0.05 + 0.45 * double(v + 1) / double(nv));
    }

    // 3. The score smoothed over the hull's voxels (a normalised Gaussian, so the outside
    // does not pull it), giving a smooth zero level for the new surface.
    auto sgrid = openvdb::FloatGrid::create(0.0f);
    sgrid->setTransform(xf.copy());
    sgrid->tree().topologyUnion(occ->tree());
    // Same topology, so the leaves come in the occupancy's order (checked).
    auto for_leaves = [&](auto& grid, auto&& body) {
        openvdb::tree::LeafManager<openvdb::FloatTree> lm(grid.tree());
        if (lm.leafCount() != nleaf) throw Error("internal: score grid topology differs from the occupancy");
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nleaf), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t l = r.begin(); l != r.end(); ++l) {
                auto& leaf = lm.leaf(l);
                if (leaf.origin() != leaves.leaf(l).origin())
                    throw Error("internal: score grid leaves out of the occupancy's order");
                std::size_t i = base[l];
                for (auto it = leaf.beginValueOn(); it; ++it) body(i++, it);
            }
        });
    };
    for_leaves(*sgrid, [&](std::size_t i, auto& it) { it.setValue(score[i]); });
    if (opt.smooth_cells > 0) {
        // Binomial passes ([1 2 1] along each axis, variance 1/2 each) normalised by the
        // weight of the hull's voxels under the kernel.
        const int passes = std::max(1, int(std::lround(2.0 * opt.smooth_cells * opt.smooth_cells)));
        auto other = sgrid->deepCopy();
        for (int k = 0; k < passes; ++k) {
            binomial_pass(*sgrid, *other);
            std::swap(sgrid, other);
        }
        for_leaves(*sgrid, [&](std::size_t i, auto& it) { score[i] = it.getValue(); });
    }

    // 3b. Coverage repair: a line of sight whose voxels all lie outside the profile gets
    // its scores lowered until its best voxel, and a band of a few cells around it, is
    // plausible; the lowering is smoothed over the image plane, so what a ray needs is a
    // smooth layer joined to its neighbours rather than a voxel of its own.
    for (std::size_t v = 0; v < nv; ++v) {
        const RayRaster& R = rasters[v];
        const auto& start = ray_start[v];
        const auto& order = ray_order[v];
        const std::size_t ncell = std::size_t(R.w) * std::size_t(R.h);
        std::vector<float> need(ncell, 0.0f);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, ncell, 256),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t c = r.begin(); c != r.end(); ++c) {
                                  const std::uint32_t k = start[c + 1] - start[c];
                                  if (k == 0) continue;
                                  float m = std::numeric_limits<float>::infinity();
                                  for (std::uint32_t q = start[c]; q < start[c + 1] && m > 0; ++q)
                                      m = std::min(m, thin[order[q]] ? -1.0f : score[order[q]]);
                                  if (m > 0) need[c] = m + std::min(0.3f, 4.0f / float(k));
                              }
                          });
        std::vector<float> lower = need;
        dilate(lower, R.w, R.h, 2);
        box_blur(lower, nullptr, R.w, R.h, 6);
        for (std::size_t c = 0; c < ncell; ++c) lower[c] = std::max(lower[c], need[c]);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, ncell, 256),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t c = r.begin(); c != r.end(); ++c)
                                  if (lower[c] > 0)
                                      for (std::uint32_t q = start[c]; q < start[c + 1]; ++q)
                                          score[order[q]] -= lower[c];
                          });
    }
    ray_start = {};
    ray_order = {};
    for_leaves(*sgrid, [&](std::size_t i, auto& it) { it.setValue(score[i]); });
    step(0.6);

    // 4. Removal, most implausible first, while every ray keeps `ray_keep` voxels.
    std::vector<std::pair<float, std::uint32_t>> cand;
    for (std::size_t i = 0; i < n; ++i) {
        if (!(score[i] > 0)) continue;
        if (thin[i]) {
            ++st.thin_kept;
            continue;
        }
        // Where one view decides the score (a flat stretch of it), the others' sum picks
        // the voxels that go first, so what stays on neighbouring rays stays together.
        cand.emplace_back(score[i] + 0.5f * total[i] / float(nv), std::uint32_t(i));
    }
    thin = {};
    st.candidates = cand.size();
    tbb::parallel_sort(cand.begin(), cand.end(), [](const auto& a, const auto& b) {
        return a.first > b.first || (a.first == b.first && a.second < b.second);
    });
    std::vector<std::uint8_t> removed(n, 0);
    std::vector<std::uint32_t> cells(nv);
    const std::uint32_t keep = std::uint32_t(std::max(1, opt.ray_keep));
    for (const auto& [s, i] : cand) {
        const Vec3d p = world_of(xf, coord[i]);
        bool ok = true;
        for (std::size_t v = 0; v < nv && ok; ++v) {
            cells[v] = rasters[v].cell(p);
            ok = ray_count[v][cells[v]] > keep;
        }
        if (!ok) {
            ++st.kept_for_rays;
            continue;
        }
        for (std::size_t v = 0; v < nv; ++v) --ray_count[v][cells[v]];
        removed[i] = 1;
        ++st.removed;
    }
    cand = {};
    step(0.7);

    // 5. The output occupancy: removed voxels off; leaves full with 26 full neighbours back
    // to tiles (so every inside point next to the outside stays a leaf voxel, volume.h).
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nleaf), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t l = r.begin(); l != r.end(); ++l) {
            std::size_t i = base[l];
            auto& leaf = leaves.leaf(l);
            std::vector<openvdb::Index> off;
            for (auto it = leaf.cbeginValueOn(); it; ++it)
                if (removed[i++]) off.push_back(it.pos());
            for (const auto o : off) leaf.setValueOff(o, false);
        }
    });
    // 5a. No plate one voxel thin where the removal cut on both sides of it: Marching Cubes
    // puts its two faces on mirrored crossings, and smoothing draws them onto one another
    // (coincident vertices). Such a voxel's removed neighbours along that axis come back
    // (only adding: every line of sight keeps what it had).
    // Two passes: a voxel put back can be such a plate along another axis, and on small or
    // lacy parts putting its neighbours back in turn would go on growing the volume.
    for (int pass = 0; pass < 2; ++pass) {
        std::vector<std::vector<Coord>> back(nleaf);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nleaf), [&](const tbb::blocked_range<std::size_t>& r) {
            auto now = occ->getConstAccessor();
            auto was = in.occupancy->getConstAccessor();
            for (std::size_t l = r.begin(); l != r.end(); ++l)
                for (auto it = leaves.leaf(l).cbeginValueOn(); it; ++it) {
                    const Coord g = it.getCoord();
                    for (int a = 0; a < 3; ++a) {
                        Coord lo = g, hi = g;
                        lo[a] -= 1;
                        hi[a] += 1;
                        if (now.isValueOn(lo) || now.isValueOn(hi)) continue;
                        const bool wl = was.isValueOn(lo), wh = was.isValueOn(hi);
                        if (!wl && !wh) continue; // thin in the hull itself
                        if (wl) back[l].push_back(lo);
                        if (wh) back[l].push_back(hi);
                    }
                }
        });
        std::size_t added = 0;
        for (const auto& b : back)
            for (const Coord& c : b)
                if (!occ->tree().isValueOn(c)) {
                    occ->tree().setValueOn(c, true);
                    ++added;
                }
        st.removed -= std::min(st.removed, added);
        st.thickened += added;
        if (added == 0) break;
    }
    {
        std::vector<Coord> full;
        for (std::size_t l = 0; l < nleaf; ++l) {
            const auto& leaf = leaves.leaf(l);
            if (!leaf.isValueMaskOn()) continue;
            bool all = true;
            for (int dx = -8; dx <= 8 && all; dx += 8)
                for (int dy = -8; dy <= 8 && all; dy += 8)
                    for (int dz = -8; dz <= 8 && all; dz += 8) {
                        const auto* nb = occ->tree().probeConstLeaf(leaf.origin().offsetBy(dx, dy, dz));
                        all = nb && nb->isValueMaskOn();
                    }
            if (all) full.push_back(leaf.origin());
        }
        for (const Coord& o : full) occ->tree().addTile(1, o, true, true);
    }
    step(0.8);

    // 6. Crossings: unchanged where an edge still runs from an inside point to a point
    // outside the hull; the smoothed score's zero crossing on edges into the removed region.
    std::shared_ptr<Volume> out = std::make_shared<Volume>();
    out->views = in.views;
    out->extra = in.extra;
    out->occupancy = occ;
    if (in.crossings) {
        auto cross = in.crossings->deepCopy();
        // The leaves to revisit: those holding removed voxels, and the ones just below in
        // x, y or z (an edge is stored at its lower end).
        std::vector<Coord> touch;
        {
            std::vector<std::uint8_t> has(nleaf, 0);
            for (std::size_t l = 0; l < nleaf; ++l)
                for (std::size_t i = base[l]; i < base[l + 1] && !has[l]; ++i) has[l] = removed[i];
            for (std::size_t l = 0; l < nleaf; ++l) {
                if (!has[l]) continue;
                const Coord o = leaves.leaf(l).origin();
                for (int a = -1; a < 3; ++a) {
                    Coord q = o;
                    if (a >= 0) q[a] -= 8;
                    touch.push_back(q);
                }
            }
        }
        std::sort(touch.begin(), touch.end());
        touch.erase(std::unique(touch.begin(), touch.end()), touch.end());
        std::vector<openvdb::Vec3fTree::LeafNodeType*> cl(touch.size());
        for (std::size_t k = 0; k < touch.size(); ++k) cl[k] = cross->tree().touchLeaf(touch[k]);
        std::atomic<std::size_t> placed{0};
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cl.size()), [&](const tbb::blocked_range<std::size_t>& r) {
            auto was = in.occupancy->getConstAccessor();
            auto now = occ->getConstAccessor();
            auto old = in.crossings->getConstAccessor();
            auto sc = sgrid->getConstAccessor();
            std::size_t mine = 0;
            for (std::size_t k = r.begin(); k != r.end(); ++k) {
                auto* leaf = cl[k];
                for (openvdb::Index off = 0; off < openvdb::Vec3fTree::LeafNodeType::SIZE; ++off) {
                    const Coord g = leaf->offsetToGlobalCoord(off);
                    const bool ig = now.isValueOn(g), rg = !ig && was.isValueOn(g);
                    openvdb::Vec3f val = old.getValue(g);
                    bool any = false;
                    for (int a = 0; a < 3; ++a) {
                        Coord q = g;
                        q[a] += 1;
                        const bool iq = now.isValueOn(q), rq = !iq && was.isValueOn(q);
                        if (ig == iq) {
                            val[a] = -1.0f;
                        } else if (rg || rq) {
                            // One end kept (inside), the other removed: the score's zero level.
                            const float sk = sc.getValue(ig ? g : q), sr = sc.getValue(ig ? q : g);
                            // A voxel kept only for a line of sight reaches almost to its
                            // removed neighbours, so it covers its whole cell of that line.
                            float f = 0.95f;
                            if (sk < 0 && sr > sk) f = std::clamp(-sk / (sr - sk), 0.0f, 1.0f);
                            val[a] = ig ? f : 1.0f - f;
                            ++mine;
                        }
                        any = any || val[a] >= 0;
                    }
                    if (any) leaf->setValueOn(off, val);
                    else leaf->setValueOff(off, openvdb::Vec3f(-1.0f));
                }
            }
            placed += mine;
        });
        st.new_crossings = placed;
        openvdb::tools::pruneInactive(cross->tree());
        out->crossings = cross;
    }
    double finest = 1e300;
    for (const auto& R : rasters) finest = std::min(finest, R.cp);
    st.cell_px = finest;
    step(1.0);
    if (stats) *stats = st;
    return out;
}

} // namespace cm
