// hull.plausible: see plausible.h. Steps: the hull's voxels are listed (tiles voxelized);
// per view they are binned into lines of sight in depth order (the tree's own columns along
// an axis, two counting sorts otherwise), which gives each voxel its run along the ray; the
// drawing's inflated profile on the same raster says how much of the run is plausible. A
// voxel's field value is its distance (cells, along the ray) outside that allowance, joined
// over the views by a smooth maximum, smoothed; where a line of sight would keep no voxel,
// the field is lowered by a smooth swelling until it keeps one; the volume keeps the voxels
// where the field is <= 0.
#include "plausible.h"

#include "plausible_steps.h"
#include "plausible_volume.h"

#include <openvdb/tree/LeafManager.h>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>

#include "core/error.h"
#include "geometry/hull_distance.h"
#include "geometry/silhouette_field.h"

namespace cm {

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
    const Lattice lat(in.transform());
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
    // The grid point of voxel i.
    auto coord_of = [&](std::size_t i) {
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
    };
    // body(i, coord) for every voxel, in parallel over leaves.
    auto for_voxels = [&](auto&& body) {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nleaf), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t l = r.begin(); l != r.end(); ++l) {
                std::size_t i = base[l];
                for (auto it = leaves.leaf(l).cbeginValueOn(); it; ++it) body(i++, it.getCoord());
            }
        });
    };
    openvdb::CoordBBox box;
    occ->tree().evalActiveVoxelBoundingBox(box);
    step(0.05);

    // 2. Per view: lines of sight, runs along them in depth order, the profile, the field.
    // phi: how far (cells, along the ray) a voxel lies outside the view's allowance, joined
    // over the views; thin: in a short run of a thin part of some drawing.
    // The views are joined by a smooth maximum (log-sum-exp over `blend` cells, less the log
    // of the count): where they agree it is their value, where one view objects mildly and
    // the others do not, the others win, so fewer lines of sight are left to swell to. The
    // values are clamped at 20 cells (far enough for any decision) to stay in range.
    const float blend = float(opt.view_blend);
    const bool soft = blend > 0;
    constexpr float kClamp = 20.0f;
    const float deep = soft ? std::exp(-kClamp / blend) : 0.0f;
    std::vector<float> phi(n, soft ? 0.0f : -std::numeric_limits<float>::infinity());
    std::vector<std::uint8_t> thin(n, 0);
    std::vector<RayRaster> rasters;
    // Per view, its voxels by line of sight (cell c: order[start[c]] .. order[start[c + 1]]).
    std::vector<std::vector<std::uint32_t>> orders, starts;
    std::vector<std::vector<std::uint32_t>> ray_total; // per view, voxels per line of sight (axis views: 0 or 1)
    const std::size_t nv = views->views.size();
    const LeafColumns columns(leaves, base);
    // body(cell, voxel indices in depth order, count, coord(k)) for every line of sight of
    // view v that holds a voxel, in parallel: the grid's columns for a view along an axis,
    // else the voxels sorted by cell and depth. coord(k) is the grid point of voxel k.
    // With `skip` (per leaf: voxels whose lines of sight are not wanted), axis views leave
    // out the columns holding one of them (the body is still asked about every other view's).
    auto for_rays = [&](std::size_t v, auto&& body, const std::vector<LeafColumns::Mask>* skip = nullptr) {
        const RayRaster& R = rasters[v];
        if (R.axis_aligned) {
            columns.for_columns(R.axis, skip,
                                [&](const Coord& first, const std::uint32_t* idx, const int* along, std::size_t cnt) {
                                    body(R.cell(first), idx, cnt, [&](std::size_t k) {
                                        Coord c = first;
                                        c[R.axis] = along[k];
                                        return c;
                                    });
                                });
            return;
        }
        const auto& order = orders[v];
        const auto& start = starts[v];
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, start.size() - 1, 256),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t c = r.begin(); c != r.end(); ++c)
                                  if (start[c + 1] > start[c]) {
                                      const std::uint32_t* idx = order.data() + start[c];
                                      body(std::uint32_t(c), idx, std::size_t(start[c + 1] - start[c]),
                                           [&](std::size_t k) { return coord_of(idx[k]); });
                                  }
                          });
    };
    for (std::size_t v = 0; v < nv; ++v) {
        const View& view = views->views[v];
        rasters.push_back(make_raster(view, lat, box, voxel));
        const RayRaster& R = rasters.back();
        const std::size_t ncell = std::size_t(R.w) * std::size_t(R.h);
        // Each line of sight's voxels in depth order (increasing or, along a negative axis,
        // decreasing: the runs are the same), with their depths in cells.
        std::vector<std::uint32_t> count(ncell, 0), key;
        orders.emplace_back();
        starts.emplace_back();
        if (R.axis_aligned) {
            // Only whether a line of sight holds a voxel is asked of an axis view's count.
            columns.for_column_points(R.axis, [&](const Coord& c) { count[R.cell(c)] = 1; });
        } else {
            std::vector<std::uint32_t> cell(n), by_depth;
            key.resize(n);
            for_voxels([&](std::size_t i, const Coord& c) {
                cell[i] = R.cell(c);
                key[i] = R.depth_key(c);
            });
            stable_bucket_order(key, R.dkeys, {}, by_depth);
            stable_bucket_order(cell, std::uint32_t(ncell), by_depth, orders[v], &starts[v]);
            for (std::size_t c = 0; c < ncell; ++c) count[c] = starts[v][c + 1] - starts[v][c];
        }

        // The drawing as these lines of sight see it (a cell is inside when a voxel of the
        // hull projects into it), its distance to the outline and local inscribed radius. The
        // distance is the drawing's own (sub-pixel), in cells; cells the hull reaches although
        // their centre is outside the drawing get 0.
        const SilhouetteSdf sdf = silhouette_sdf(view.coverage, view.name);
        std::vector<char> outside(ncell, 0);
        std::vector<float> dist(ncell, 0.0f);
        tbb::parallel_for(tbb::blocked_range<int>(0, R.h), [&](const tbb::blocked_range<int>& rows) {
            for (int j = rows.begin(); j != rows.end(); ++j)
                for (int i = 0; i < R.w; ++i) {
                    const std::size_t c = std::size_t(j) * std::size_t(R.w) + std::size_t(i);
                    if (count[c] == 0) {
                        outside[c] = 1;
                        continue;
                    }
                    const double px = R.x0 + (i + 0.5) * R.cp, py = R.y0 + (j + 0.5) * R.cp;
                    dist[c] = float(std::max(0.0, -sdf.sample(px, py) / R.cp));
                }
        });
        // The local inscribed radius steps where one disc takes over from another; blurred
        // over the drawing, the profile (and the surface) has no creases there.
        std::vector<float> radius = local_inscribed_radius(dist, R.w, R.h);
        box_blur(radius, &outside, R.w, R.h, 4);
        for (std::size_t c = 0; c < ncell; ++c) radius[c] = std::max(radius[c], dist[c]);

        // The field of one line of sight: `dep` the depths (cells) of its voxels `idx`.
        const double gap = R.gap_keys * R.dq / voxel;
        auto score = [&](std::uint32_t c, const std::uint32_t* idx, const double* dep, std::size_t cnt) {
            const double frac =
                profile_fraction(radius[c] > 0 ? dist[c] / radius[c] : 0.0, opt.profile_exponent, opt.roundness);
            // The inflated cross-section's own half-depth (radius R), so a round drawing is a
            // round solid even where the run is long.
            const double inflated = frac * double(radius[c]);
            // A short run well inside the drawing is a thin part seen face-on (an ear, a fin);
            // near the outline short runs are the rim of any body.
            const bool thin_part = dist[c] >= 1.5f && radius[c] <= 2.0f * float(opt.thin_cells);
            for (std::size_t rb = 0; rb != cnt;) {
                std::size_t re = rb + 1;
                while (re != cnt && std::abs(dep[re] - dep[re - 1]) <= gap) ++re;
                const double front = std::min(dep[rb], dep[re - 1]) - 0.5, back = std::max(dep[rb], dep[re - 1]) + 0.5;
                const double half = 0.5 * (back - front), mid = 0.5 * (back + front);
                // Allowed half-depth: the larger of the profile's share of the run and the
                // inflated cross-section (within the run).
                const double allow = std::max(frac * half, std::min(half, inflated));
                const bool is_thin = thin_part && re - rb <= std::size_t(opt.thin_cells);
                for (std::size_t k = rb; k != re; ++k) {
                    const float sv = float(std::abs(dep[k] - mid) - allow);
                    // (Deep inside the allowance, the common case, the clamped value's exponential
                    // is a constant.)
                    if (soft) phi[idx[k]] += sv <= -kClamp ? deep : std::exp(std::clamp(sv, -kClamp, kClamp) / blend);
                    else phi[idx[k]] = std::max(phi[idx[k]], sv);
                    if (is_thin) thin[idx[k]] = 1;
                }
                rb = re;
            }
        };
        tbb::enumerable_thread_specific<std::vector<double>> depths;
        if (R.axis_aligned) {
            columns.for_columns(R.axis,
                                [&](const Coord& first, const std::uint32_t* idx, const int* along, std::size_t cnt) {
                                    auto& dep = depths.local();
                                    dep.assign(along, along + cnt);
                                    score(R.cell(first), idx, dep.data(), cnt);
                                });
        } else {
            for_rays(v, [&](std::uint32_t c, const std::uint32_t* idx, std::size_t cnt, auto&&) {
                auto& dep = depths.local();
                dep.resize(cnt);
                for (std::size_t k = 0; k < cnt; ++k) dep[k] = R.depth_of_key(key[idx[k]]) / voxel;
                score(c, idx, dep.data(), cnt);
            });
        }
        ray_total.push_back(std::move(count));
        step(0.05 + 0.4 * double(v + 1) / double(nv));
    }

    if (soft) {
        // Deep inside every view's allowance (the sum of the constants, added in the same
        // order) the value is a constant too.
        float all_deep = 0.0f;
        for (std::size_t v = 0; v < nv; ++v) all_deep += deep;
        const float deep_value = blend * std::log(all_deep / float(nv));
        tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
            phi[i] = phi[i] == all_deep ? deep_value : blend * std::log(phi[i] / float(nv));
        });
    }
    // 3. The field smoothed over the hull's voxels (a normalised Gaussian, so the outside
    // does not pull it), giving a smooth zero level for the new surface. Leaves whose values
    // all lie farther from 0 than the kernel can carry them keep their values.
    // The smoothing is given in cells of a grid of 256 along the object's longest side, so
    // the surface is as smooth at any resolution; voxels farther from the zero level than
    // four standard deviations keep their values (their side of it is not in doubt).
    {
        const double sigma = opt.smooth_cells * double(std::max({box.dim().x(), box.dim().y(), box.dim().z()})) / 256.0;
        smooth_field(phi, leaves, base, box, sigma, float(4.0 * sigma + 2.0));
    }
    // Thin parts have no volume to spare.
    {
        std::atomic<std::size_t> kept{0}, cand{0};
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n), [&](const tbb::blocked_range<std::size_t>& r) {
            std::size_t k = 0, c = 0;
            for (std::size_t i = r.begin(); i != r.end(); ++i) {
                if (!(phi[i] > 0)) continue;
                if (thin[i]) {
                    ++k;
                    phi[i] = -0.5f;
                } else {
                    ++c;
                }
            }
            kept += k;
            cand += c;
        });
        st.thin_kept = kept;
        st.candidates = cand;
    }
    thin = {};
    step(0.55);

    // 4. Every line of sight keeps min(ray_keep, its voxels) voxels with field <= 0. Where the
    // profiles leave one short, (a) the field is lowered about the ray's best voxels by a
    // smooth swelling; (b) what that keeps apart from the profiles' volume would float free,
    // so it goes; (c) the volume itself swells to the lines of sight still short: a ball about
    // its kept voxel nearest to each (in the nearest covered line of sight of that view, at the
    // depth the field prefers) reaching the ray's nearest voxel, joined to the field by a
    // smooth minimum. So the volume bulges out, in one piece, instead of keeping loose strands
    // along the rays. The field only goes down from (a) on, so no line of sight loses a voxel;
    // (d) keeps the best voxels of any line of sight the coarsely sampled swellings still miss.
    const std::uint32_t keep = std::uint32_t(std::max(1, opt.ray_keep));
    constexpr float kMargin = 0.75f; // cells of field below 0 a needed voxel gets
    constexpr float kBlend = 1.5f;   // cells over which a ball blends into the field
    const int maxdim = std::max({box.dim().x(), box.dim().y(), box.dim().z()});
    std::vector<float> cur = phi;
    struct Vox {
        std::uint32_t cell, i;
        Coord c;
    };
    // The voxels with field <= 0 of the cells with `want[cell]` set, by cell, in depth order.
    auto kept_voxels_of = [&](std::size_t v, const std::vector<char>& want) {
        tbb::enumerable_thread_specific<std::vector<Vox>> found;
        for_rays(v, [&](std::uint32_t c, const std::uint32_t* idx, std::size_t cnt, auto&& coord) {
            if (!want[c]) return;
            auto& local = found.local();
            for (std::size_t k = 0; k < cnt; ++k)
                if (cur[idx[k]] <= 0) local.push_back({c, idx[k], coord(k)});
        });
        std::vector<Vox> all;
        for (auto& f : found) all.insert(all.end(), f.begin(), f.end());
        // A cell's voxels come whole from one call of the body.
        std::stable_sort(all.begin(), all.end(), [](const Vox& a, const Vox& b) { return a.cell < b.cell; });
        return all;
    };
    // Per view, the voxels of its lines of sight the profiles leave short, by line of sight
    // (the field only goes down from here, and what 4b drops was never the profiles', so no
    // other line of sight can become short): those within 8 cells of field of the best, where
    // a swelling can reach (a voxel left out only makes a line of sight look shorter than
    // it is: more swelling, never less coverage).
    std::vector<std::vector<Vox>> lists(nv);
    std::vector<std::vector<std::size_t>> groups(nv); // start of each line of sight in lists[v]
    // With one voxel to keep, a line of sight holding a kept voxel is not short: axis views
    // skip the grid columns through the kept voxels without dealing them.
    std::vector<LeafColumns::Mask> kept_mask;
    if (keep == 1) {
        kept_mask.resize(nleaf);
        tbb::parallel_for(std::size_t(0), nleaf, [&](std::size_t l) {
            LeafColumns::Mask& m = kept_mask[l];
            const auto& mask = leaves.leaf(l).getValueMask();
            std::size_t i = base[l];
            for (openvdb::Index w = 0; w < 8; ++w) {
                m[w] = 0;
                for (std::uint64_t word = mask.getWord<std::uint64_t>(w); word; word &= word - 1, ++i)
                    if (cur[i] <= 0) m[w] |= std::uint64_t(1) << __builtin_ctzll(word);
            }
        });
    }
    for (std::size_t v = 0; v < nv; ++v) {
        tbb::enumerable_thread_specific<std::vector<Vox>> found;
        for_rays(
            v,
            [&](std::uint32_t c, const std::uint32_t* idx, std::size_t cnt, auto&& coord) {
                std::uint32_t kept = 0;
                const std::uint32_t want = std::min(keep, std::uint32_t(cnt));
                float best = std::numeric_limits<float>::infinity();
                for (std::size_t k = 0; k < cnt; ++k) {
                    kept += cur[idx[k]] <= 0;
                    best = std::min(best, cur[idx[k]]);
                }
                if (kept >= want) return;
                auto& local = found.local();
                for (std::size_t k = 0; k < cnt; ++k)
                    if (cur[idx[k]] <= best + 8.0f) local.push_back({c, idx[k], coord(k)});
            },
            kept_mask.empty() ? nullptr : &kept_mask);
        for (auto& f : found) lists[v].insert(lists[v].end(), f.begin(), f.end());
        for (std::size_t k = 0; k < lists[v].size(); ++k)
            if (k == 0 || lists[v][k].cell != lists[v][k - 1].cell) groups[v].push_back(k);
        if (lists[v].empty()) continue;
        groups[v].push_back(lists[v].size());
        st.short_rays += groups[v].size() - 1;
    }
    // Whether line of sight g of view v is short, and the field value its `want`-th best voxel has.
    auto shortfall = [&](std::size_t v, std::size_t g, float* t) {
        const auto& list = lists[v];
        const std::size_t b = groups[v][g], e = groups[v][g + 1];
        static thread_local std::vector<float> vals;
        vals.clear();
        std::uint32_t have = 0;
        for (std::size_t k = b; k < e; ++k) {
            vals.push_back(cur[list[k].i]);
            have += cur[list[k].i] <= 0;
        }
        const std::size_t want = std::min<std::size_t>(keep, vals.size());
        if (have >= want) return false;
        std::nth_element(vals.begin(), vals.begin() + std::ptrdiff_t(want - 1), vals.end());
        *t = vals[want - 1];
        return true;
    };

    // 4a. The swelling about the best voxels of each short line of sight (those within a cell
    // of the best: where the profiles least object), in rounds since its smoothing takes some
    // of its height.
    {
        SwellField swell(box, std::clamp(int(std::lround(double(maxdim) / 96.0)), 1, 8));
        for (int round = 0; round < 4; ++round) {
            // The seeds, found in parallel (settle() sorts them, so their order does not matter).
            tbb::enumerable_thread_specific<std::vector<std::pair<Coord, float>>> seeds;
            for (std::size_t v = 0; v < nv; ++v)
                tbb::parallel_for(std::size_t(0), groups[v].empty() ? 0 : groups[v].size() - 1, [&](std::size_t g) {
                    float t = 0;
                    if (!shortfall(v, g, &t)) return;
                    auto& local = seeds.local();
                    for (std::size_t k = groups[v][g]; k < groups[v][g + 1]; ++k)
                        if (cur[lists[v][k].i] <= t + 1.0f) local.push_back({lists[v][k].c, t + kMargin});
                });
            bool seeded = false;
            for (const auto& local : seeds)
                for (const auto& [c, value] : local) swell.seed(c, value), seeded = true;
            if (!seeded) break;
            swell.settle();
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nleaf), [&](const tbb::blocked_range<std::size_t>& r) {
                for (std::size_t l = r.begin(); l != r.end(); ++l) {
                    const auto& leaf = leaves.leaf(l);
                    if (!swell.raised_in(openvdb::CoordBBox::createCube(leaf.origin(), LeafT::DIM))) continue;
                    const SwellField::Block block(swell, leaf.origin());
                    std::size_t i = base[l];
                    for (openvdb::Index w = 0; w < 8; ++w)
                        for (std::uint64_t bits = leaf.getValueMask().getWord<std::uint64_t>(w); bits;
                             bits &= bits - 1, ++i) {
                            if (!(phi[i] > 0)) continue;
                            const int b = __builtin_ctzll(bits);
                            cur[i] = std::min(cur[i], phi[i] - block.at(int(w), b >> 3, b & 7));
                        }
                }
            });
        }
    }
    // 4b. What the swelling kept apart from the profiles' volume goes: a flood from the
    // profiles' volume through the swollen voxels, and what it misses.
    {
        std::vector<LeafColumns::Mask> member(nleaf), anchor(nleaf);
        tbb::parallel_for(std::size_t(0), nleaf, [&](std::size_t l) {
            const auto& mask = leaves.leaf(l).getValueMask();
            std::size_t i = base[l];
            for (openvdb::Index w = 0; w < 8; ++w) {
                std::uint64_t m = 0, a = 0;
                for (std::uint64_t bits = mask.getWord<std::uint64_t>(w); bits; bits &= bits - 1, ++i) {
                    const std::uint64_t bit = bits & (~bits + 1);
                    if (phi[i] <= 0) a |= bit;
                    else if (cur[i] <= 0) m |= bit;
                }
                member[l][w] = m, anchor[l][w] = a;
            }
        });
        const std::vector<LeafColumns::Mask> joined = flood(leaves, anchor, member, /*missing_is_seed=*/false);
        anchor = {};
        st.loose_dropped = tbb::parallel_reduce(
            tbb::blocked_range<std::size_t>(0, nleaf), std::size_t(0),
            [&](const tbb::blocked_range<std::size_t>& r, std::size_t dropped) {
                for (std::size_t l = r.begin(); l != r.end(); ++l) {
                    std::uint64_t loose_any = 0;
                    for (openvdb::Index w = 0; w < 8; ++w) loose_any |= member[l][w] & ~joined[l][w];
                    if (!loose_any) continue;
                    const auto& mask = leaves.leaf(l).getValueMask();
                    std::size_t i = base[l];
                    for (openvdb::Index w = 0; w < 8; ++w) {
                        const std::uint64_t loose = member[l][w] & ~joined[l][w];
                        for (std::uint64_t bits = mask.getWord<std::uint64_t>(w); bits; bits &= bits - 1, ++i)
                            if (loose & bits & (~bits + 1)) cur[i] = phi[i], ++dropped;
                    }
                }
                return dropped;
            },
            std::plus<>());
    }
    // 4c. Balls about the volume to the lines of sight still short.
    BallField balls(box, std::clamp(int(std::lround(double(maxdim) / 128.0)), 1, 4));
    const double coarse = double(std::clamp(int(std::lround(double(maxdim) / 128.0)), 1, 4));
    auto dist2 = [](const Coord& a, const Coord& b) {
        const double dx = a.x() - b.x(), dy = a.y() - b.y(), dz = a.z() - b.z();
        return dx * dx + dy * dy + dz * dz;
    };
    for (std::size_t v = 0; v < nv; ++v) {
        const RayRaster& R = rasters[v];
        const std::size_t ncell = ray_total[v].size();
        // 1: short, 2: covered (holds a kept voxel).
        std::vector<char> flag(ncell, 0);
        for (std::size_t c = 0; c < ncell; ++c) flag[c] = ray_total[v][c] > 0 ? 2 : 0;
        bool any = false;
        std::vector<std::size_t> short_groups;
        for (std::size_t g = 0; g + 1 < groups[v].size(); ++g) {
            const std::uint32_t c = lists[v][groups[v][g]].cell;
            float t = 0;
            bool kept_one = false;
            for (std::size_t k = groups[v][g]; k < groups[v][g + 1]; ++k)
                kept_one = kept_one || cur[lists[v][k].i] <= 0;
            flag[c] = kept_one ? 2 : 0;
            if (shortfall(v, g, &t)) flag[c] = 1, any = true, short_groups.push_back(g);
        }
        if (!any) continue;
        st.ball_rays += short_groups.size();
        // The nearest covered cell of every cell (8-neighbour breadth-first search).
        constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
        std::vector<std::uint32_t> near(ncell, none);
        std::vector<std::uint32_t> queue;
        for (std::size_t c = 0; c < ncell; ++c)
            if (flag[c] == 2) near[c] = std::uint32_t(c), queue.push_back(std::uint32_t(c));
        for (std::size_t h = 0; h < queue.size(); ++h) {
            const std::uint32_t c = queue[h];
            const int i = int(c % std::uint32_t(R.w)), j = int(c / std::uint32_t(R.w));
            for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di) {
                    const int x = i + di, y = j + dj;
                    if (x < 0 || y < 0 || x >= R.w || y >= R.h) continue;
                    const std::size_t q = std::size_t(y) * std::size_t(R.w) + std::size_t(x);
                    if (near[q] != none) continue;
                    near[q] = near[c];
                    queue.push_back(std::uint32_t(q));
                }
        }
        queue = {};
        std::vector<char> anchor(ncell, 0);
        for (std::size_t g : short_groups) {
            const std::uint32_t c = lists[v][groups[v][g]].cell;
            if (near[c] != none) anchor[near[c]] = 1;
        }
        const std::vector<Vox> anchors = kept_voxels_of(v, anchor);
        tbb::enumerable_thread_specific<std::vector<std::pair<openvdb::Vec3d, double>>> found;
        tbb::parallel_for(std::size_t(0), short_groups.size(), [&](std::size_t s) {
            const std::size_t g = short_groups[s];
            const auto rb = lists[v].begin() + std::ptrdiff_t(groups[v][g]),
                       re = lists[v].begin() + std::ptrdiff_t(groups[v][g + 1]);
            const std::uint32_t c = rb->cell;
            if (near[c] == none) return; // nothing kept in this view
            auto ab = std::lower_bound(anchors.begin(), anchors.end(), near[c],
                                       [](const Vox& a, std::uint32_t x) { return a.cell < x; });
            auto ae = ab;
            while (ae != anchors.end() && ae->cell == near[c]) ++ae;
            if (ab == ae) return;
            // The depth the field prefers: the ray's best voxel.
            const auto best = std::min_element(rb, re, [&](const Vox& a, const Vox& b) { return cur[a.i] < cur[b.i]; });
            const auto centre = std::min_element(
                ab, ae, [&](const Vox& a, const Vox& b) { return dist2(a.c, best->c) < dist2(b.c, best->c); });
            // The ray's `want` voxels nearest to the centre: the ball reaches the farthest.
            std::vector<double> d;
            for (auto it = rb; it != re; ++it) d.push_back(dist2(it->c, centre->c));
            const std::size_t want = std::min<std::size_t>(keep, d.size());
            std::nth_element(d.begin(), d.begin() + std::ptrdiff_t(want - 1), d.end());
            const auto& o = centre->c;
            found.local().push_back(
                {openvdb::Vec3d(o.x(), o.y(), o.z()), std::sqrt(d[want - 1]) + kMargin + 0.5 * coarse});
        });
        for (auto& f : found)
            for (const auto& [centre, radius] : f) balls.add(centre, radius);
        balls.settle(kBlend + 2.0 * coarse);
        // Smooth minimum of the field and the balls (never above either).
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nleaf), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t l = r.begin(); l != r.end(); ++l) {
                if (!balls.any_in(openvdb::CoordBBox::createCube(leaves.leaf(l).origin(), LeafT::DIM))) continue;
                std::size_t i = base[l];
                for (auto it = leaves.leaf(l).cbeginValueOn(); it; ++it, ++i) {
                    const float b = balls.at(it.getCoord()), a = cur[i];
                    if (!(b < a + kBlend)) continue;
                    const float h = std::clamp(0.5f + 0.5f * (a - b) / kBlend, 0.0f, 1.0f);
                    cur[i] = std::min(a, a + (b - a) * h - kBlend * h * (1.0f - h));
                }
            }
        });
    };
    // 4d. Any line of sight still short keeps its best voxels.
    for (std::size_t v = 0; v < nv; ++v)
        for (std::size_t g = 0; g + 1 < groups[v].size(); ++g) {
            float t = 0;
            if (!shortfall(v, g, &t)) continue;
            for (std::size_t k = groups[v][g]; k < groups[v][g + 1]; ++k)
                if (cur[lists[v][k].i] <= t) cur[lists[v][k].i] = std::min(cur[lists[v][k].i], -kMargin);
        }
    lists = {};
    orders = {};
    starts = {};
    step(0.65);

    // 5. Removal: the voxels where the field is above 0.
    std::vector<std::uint8_t> removed(n, 0);
    {
        std::atomic<std::size_t> count{0};
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n), [&](const tbb::blocked_range<std::size_t>& r) {
            std::size_t k = 0;
            for (std::size_t i = r.begin(); i != r.end(); ++i) {
                removed[i] = cur[i] > 0;
                k += removed[i];
            }
            count += k;
        });
        st.removed = count;
        st.kept_for_rays = st.candidates > st.removed ? st.candidates - st.removed : 0;
    }
    phi = {};
    step(0.7);
    // 6-7. The output volume: occupancy and crossings (plausible_volume.cpp).
    std::shared_ptr<Volume> out = plausible_volume(in, occ, leaves, base, removed, cur, maxdim, st, step);
    double finest = 1e300;
    for (const auto& R : rasters) finest = std::min(finest, R.cp);
    st.cell_px = finest;
    step(1.0);
    if (stats) *stats = st;
    return out;
}

} // namespace cm
