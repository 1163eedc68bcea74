// Step 4 of hull.plausible (plausible_state.h): every line of sight keeps min(ray_keep, its
// voxels) voxels with field <= 0. Where the profiles leave one short, (a) the field is lowered
// about the ray's best voxels by a smooth swelling; (b) what that keeps apart from the
// profiles' volume would float free, so it goes; (c) the volume itself swells to the lines of
// sight still short: a ball about its kept voxel nearest to each (in the nearest covered line
// of sight of that view, at the depth the field prefers) reaching the ray's nearest voxel,
// joined to the field by a smooth minimum. So the volume bulges out, in one piece, instead of
// keeping loose strands along the rays. The field only goes down from (a) on, so no line of
// sight loses a voxel; (d) keeps the best voxels of any line of sight the coarsely sampled
// swellings still miss.
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <utility>

#include "leaf_masks.h"
#include "plausible_state.h"

namespace cm::plausible {

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

double dist2(const Coord& a, const Coord& b) {
    const double dx = a.x() - b.x(), dy = a.y() - b.y(), dz = a.z() - b.z();
    return dx * dx + dy * dy + dz * dz;
}

// Bit k for each of the 64 values from `value` that is <= 0 (a full word of a leaf's voxels):
// eight at a time, which the compiler does without branches.
std::uint64_t kept_bits(const float* value) {
    std::uint64_t bits = 0;
    for (int b = 0; b < 8; ++b) {
        unsigned byte = 0;
        for (int k = 0; k < 8; ++k) byte |= unsigned(value[8 * b + k] <= 0) << k;
        bits |= std::uint64_t(byte) << (8 * b);
    }
    return bits;
}

// The nearest covered cell (flag 2) of every cell of the raster (8-neighbour breadth-first
// search); kNone where the view has none.
std::vector<std::uint32_t> nearest_covered(const RayRaster& R, const std::vector<char>& flag) {
    const std::size_t ncell = flag.size();
    std::vector<std::uint32_t> near(ncell, kNone);
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
                if (near[q] != kNone) continue;
                near[q] = near[c];
                queue.push_back(std::uint32_t(q));
            }
    }
    return near;
}

} // namespace

void Plausible::cover_lines_of_sight() {
    keep_ = std::uint32_t(std::max(1, opt_.ray_keep));
    // The field is lowered in place, once, by drop_loose(): until then cur_ holds the values
    // before the swelling, and its rounds need only the short lines' voxels lowered (low_).
    cur_.swap(phi_);
    find_short_lines();
    swell();            // (a)
    drop_loose();       // (b)
    reach_with_balls(); // (c)
    keep_best();        // (d)
    lists_ = {};
    groups_ = {};
    orders_ = {};
    starts_ = {};
    swelling_.reset();
    swollen_ = {};
    low_ = {};
    kept_ = {};
}

// Per view, the voxels of its lines of sight the profiles leave short, by line of sight (the
// field only goes down from here, and what (b) drops was never the profiles', so no other line
// of sight can become short): those within 8 cells of field of the best, where a swelling can
// reach (a voxel left out only makes a line of sight look shorter than it is: more swelling,
// never less coverage).
void Plausible::find_short_lines() {
    lists_.assign(nv_, {});
    groups_.assign(nv_, {});
    // The kept voxels (field <= 0). With one voxel to keep, a line of sight holding one is not
    // short: axis views skip the grid columns through them without dealing them. (drop_loose()
    // takes them too, where the swelling did not reach.)
    kept_.resize(vox_.nleaf);
    tbb::parallel_for(std::size_t(0), vox_.nleaf, [&](std::size_t l) {
        LeafColumns::Mask& m = kept_[l];
        const auto& mask = vox_.leaves.leaf(l).getValueMask();
        std::size_t i = vox_.base[l];
        for (openvdb::Index w = 0; w < 8; ++w) {
            std::uint64_t word = mask.getWord<std::uint64_t>(w);
            if (word == ~std::uint64_t(0)) {
                m[w] = kept_bits(&cur_[i]);
                i += 64;
                continue;
            }
            m[w] = 0;
            for (; word; word &= word - 1, ++i)
                if (cur_[i] <= 0) m[w] |= std::uint64_t(1) << __builtin_ctzll(word);
        }
    });
    for (std::size_t v = 0; v < nv_; ++v) {
        tbb::enumerable_thread_specific<std::vector<Vox>> found;
        for_rays(
            v,
            [&](std::uint32_t c, const std::uint32_t* idx, std::size_t cnt, auto&& coord) {
                std::uint32_t kept = 0;
                const std::uint32_t want = std::min(keep_, std::uint32_t(cnt));
                float best = std::numeric_limits<float>::infinity();
                for (std::size_t k = 0; k < cnt; ++k) {
                    kept += cur_[idx[k]] <= 0;
                    best = std::min(best, cur_[idx[k]]);
                }
                if (kept >= want) return;
                auto& local = found.local();
                for (std::size_t k = 0; k < cnt; ++k)
                    if (cur_[idx[k]] <= best + 8.0f) local.push_back({c, idx[k], coord(k)});
            },
            keep_ == 1 ? &kept_ : nullptr);
        auto& list = lists_[v];
        auto& group = groups_[v];
        // The threads' finds joined: the largest taken whole, the others after it (a line of
        // sight comes whole from one call of the body, and their order does not matter).
        std::vector<Vox>* largest = nullptr;
        for (auto& f : found)
            if (!largest || f.size() > largest->size()) largest = &f;
        if (largest) list = std::move(*largest);
        for (auto& f : found)
            if (&f != largest) list.insert(list.end(), f.begin(), f.end());
        for (std::size_t k = 0; k < list.size(); ++k)
            if (k == 0 || list[k].cell != list[k - 1].cell) group.push_back(k);
        if (list.empty()) continue;
        group.push_back(list.size());
        st_.short_rays += group.size() - 1;
    }
}

// Whether line of sight g of view v is short, and the field value its `keep_`-th best voxel has.
bool Plausible::shortfall(std::size_t v, std::size_t g, float* t, const float* low) const {
    const auto& list = lists_[v];
    const std::size_t b = groups_[v][g], e = groups_[v][g + 1];
    if (keep_ == 1) { // short when no value is <= 0; the best is the smallest
        float best = std::numeric_limits<float>::infinity();
        for (std::size_t k = b; k < e; ++k) {
            const float value = low ? low[k] : cur_[list[k].i];
            if (value <= 0) return false;
            best = std::min(best, value);
        }
        *t = best;
        return true;
    }
    static thread_local std::vector<float> vals;
    vals.clear();
    std::uint32_t have = 0;
    for (std::size_t k = b; k < e; ++k) {
        const float value = low ? low[k] : cur_[list[k].i];
        vals.push_back(value);
        have += value <= 0;
    }
    const std::size_t want = std::min<std::size_t>(keep_, vals.size());
    if (have >= want) return false;
    std::nth_element(vals.begin(), vals.begin() + std::ptrdiff_t(want - 1), vals.end());
    *t = vals[want - 1];
    return true;
}

// The voxels with field <= 0 of the cells with `want[cell]` set, by cell, in depth order.
std::vector<Vox> Plausible::kept_voxels_of(std::size_t v, const std::vector<char>& want) const {
    tbb::enumerable_thread_specific<std::vector<Vox>> found;
    for_rays_in(v, want, [&](std::uint32_t c, const std::uint32_t* idx, std::size_t cnt, auto&& coord) {
        auto& local = found.local();
        for (std::size_t k = 0; k < cnt; ++k)
            if (cur_[idx[k]] <= 0) local.push_back({c, idx[k], coord(k)});
    });
    std::vector<Vox> all;
    for (auto& f : found) all.insert(all.end(), f.begin(), f.end());
    // A cell's voxels come whole from one call of the body.
    std::stable_sort(all.begin(), all.end(), [](const Vox& a, const Vox& b) { return a.cell < b.cell; });
    return all;
}

// (a) The swelling about the best voxels of each short line of sight (those within a cell of
// the best: where the profiles least object), in rounds since its smoothing takes some of its
// height. The swelling only rises (SwellField::settle() adds), so a voxel's value lowered by
// every round so far is its value less the swelling now: the rounds read it for the voxels of
// the lines still short alone (low_; values only go down, so a line covered stays covered),
// and drop_loose() lowers the field once.
void Plausible::swell() {
    swelling_ = std::make_unique<SwellField>(vox_.box, std::clamp(int(std::lround(double(vox_.maxdim) / 96.0)), 1, 8));
    SwellField& field = *swelling_;
    swollen_.assign(vox_.nleaf, 0);
    low_.assign(nv_, {});
    std::vector<std::vector<char>> covered(nv_);
    for (std::size_t v = 0; v < nv_; ++v) {
        low_[v].resize(lists_[v].size());
        covered[v].assign(groups_[v].empty() ? 0 : groups_[v].size() - 1, 0);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, lists_[v].size()),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t k = r.begin(); k != r.end(); ++k) low_[v][k] = cur_[lists_[v][k].i];
                          });
    }
    constexpr int kRounds = 4;
    for (int round = 0; round < kRounds; ++round) {
        // The seeds, found in parallel (settle() sorts them, so their order does not matter).
        tbb::enumerable_thread_specific<std::vector<std::pair<Coord, float>>> seeds;
        for (std::size_t v = 0; v < nv_; ++v)
            tbb::parallel_for(std::size_t(0), covered[v].size(), [&](std::size_t g) {
                float t = 0;
                if (covered[v][g]) return;
                if (!shortfall(v, g, &t, low_[v].data())) {
                    covered[v][g] = 1;
                    return;
                }
                auto& local = seeds.local();
                for (std::size_t k = groups_[v][g]; k < groups_[v][g + 1]; ++k)
                    if (low_[v][k] <= t + 1.0f) local.push_back({lists_[v][k].c, t + kMargin});
            });
        bool seeded = false;
        for (const auto& local : seeds)
            for (const auto& [c, value] : local) field.seed(c, value), seeded = true;
        if (!seeded) break;
        field.settle();
        mark_swollen(field);
        if (round + 1 < kRounds) lower_lists(field, covered);
    }
}

// The leaves about which the last round raised the swelling.
void Plausible::mark_swollen(const SwellField& field) {
    tbb::parallel_for(std::size_t(0), vox_.nleaf, [&](std::size_t l) {
        if (!swollen_[l] && field.raised_in(openvdb::CoordBBox::createCube(vox_.leaves.leaf(l).origin(), LeafT::DIM)))
            swollen_[l] = 1;
    });
}

// The voxels of the lines still short lowered by the swelling (only where the profiles
// object; SwellField::at() is SwellField::Block::at()'s value).
void Plausible::lower_lists(const SwellField& field, const std::vector<std::vector<char>>& covered) {
    for (std::size_t v = 0; v < nv_; ++v)
        tbb::parallel_for(std::size_t(0), covered[v].size(), [&](std::size_t g) {
            if (covered[v][g]) return;
            for (std::size_t k = groups_[v][g]; k < groups_[v][g + 1]; ++k) {
                const float phi = cur_[lists_[v][k].i];
                if (phi > 0) low_[v][k] = phi - field.at(lists_[v][k].c);
            }
        });
}

// (b) What the swelling kept apart from the profiles' volume goes: a flood from the profiles'
// volume through the swollen voxels, and what it misses. The field is lowered here, once, in
// the leaves the swelling reached (cur_ holds the values before it until then): at once where
// it stays above 0, after the flood for the voxels it takes to 0 or below (`member`), which
// keep their values if loose.
void Plausible::drop_loose() {
    const std::size_t nleaf = vox_.nleaf;
    std::vector<LeafColumns::Mask> member(nleaf), anchor(nleaf);
    tbb::parallel_for(std::size_t(0), nleaf, [&](std::size_t l) {
        const auto& leaf = vox_.leaves.leaf(l);
        const auto& mask = leaf.getValueMask();
        // Where the swelling did not reach, the field is as find_short_lines() found it.
        if (!swollen_[l]) {
            member[l] = {};
            anchor[l] = kept_[l];
            return;
        }
        std::size_t i = vox_.base[l];
        const SwellField::Block block(*swelling_, leaf.origin());
        for (openvdb::Index w = 0; w < 8; ++w) {
            std::uint64_t m = 0, a = 0;
            for (std::uint64_t bits = mask.getWord<std::uint64_t>(w); bits; bits &= bits - 1, ++i) {
                const std::uint64_t bit = bits & (~bits + 1);
                const float phi = cur_[i];
                if (!(phi > 0)) {
                    a |= bit;
                    continue;
                }
                const int b = __builtin_ctzll(bits);
                const float lowered = phi - block.at(int(w), b >> 3, b & 7);
                if (lowered <= 0) m |= bit;
                else cur_[i] = lowered;
            }
            member[l][w] = m, anchor[l][w] = a;
        }
    });
    const std::vector<LeafColumns::Mask> joined = flood(vox_.leaves, anchor, member, /*missing_is_seed=*/false);
    anchor = {};
    st_.loose_dropped = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, nleaf), std::size_t(0),
        [&](const tbb::blocked_range<std::size_t>& r, std::size_t dropped) {
            for (std::size_t l = r.begin(); l != r.end(); ++l) dropped += lower_members(l, member[l], joined[l]);
            return dropped;
        },
        std::plus<>());
}

// Leaf l's `member` voxels lowered by the swelling, but for the loose ones (those the flood
// missed: not in `joined`), which keep their values; returns how many those are.
std::size_t Plausible::lower_members(std::size_t l, const LeafColumns::Mask& member, const LeafColumns::Mask& joined) {
    std::uint64_t any = 0;
    for (openvdb::Index w = 0; w < 8; ++w) any |= member[w];
    if (!any) return 0;
    const auto& leaf = vox_.leaves.leaf(l);
    const SwellField::Block block(*swelling_, leaf.origin());
    std::size_t i = vox_.base[l], dropped = 0;
    for (openvdb::Index w = 0; w < 8; ++w)
        for (std::uint64_t bits = leaf.getValueMask().getWord<std::uint64_t>(w); bits; bits &= bits - 1, ++i) {
            const std::uint64_t bit = bits & (~bits + 1);
            if (!(member[w] & bit)) continue;
            if (!(joined[w] & bit)) {
                ++dropped;
                continue;
            }
            const int b = __builtin_ctzll(bits);
            cur_[i] = cur_[i] - block.at(int(w), b >> 3, b & 7);
        }
    return dropped;
}

// (c) Balls about the volume to the lines of sight still short, view by view.
void Plausible::reach_with_balls() {
    BallField balls(vox_.box, std::clamp(int(std::lround(double(vox_.maxdim) / 128.0)), 1, 4));
    const double coarse = double(std::clamp(int(std::lround(double(vox_.maxdim) / 128.0)), 1, 4));
    for (std::size_t v = 0; v < nv_; ++v) balls_for_view(v, balls, coarse);
}

void Plausible::balls_for_view(std::size_t v, BallField& balls, double coarse) {
    std::vector<char> flag;
    std::vector<std::size_t> short_groups;
    if (!short_lines_of(v, flag, short_groups)) return;
    st_.ball_rays += short_groups.size();
    const std::vector<std::uint32_t> near = nearest_covered(rasters_[v], flag);
    add_balls(v, short_groups, near, balls, coarse);
    balls.settle(kBlend + 2.0 * coarse);
    blend_balls(balls);
}

// The lines of sight of view v: `flag` 1 short, 2 covered (holds a kept voxel); the short
// ones' groups. False when none is short.
bool Plausible::short_lines_of(std::size_t v, std::vector<char>& flag, std::vector<std::size_t>& short_groups) const {
    const std::size_t ncell = ray_total_[v].size();
    flag.assign(ncell, 0);
    for (std::size_t c = 0; c < ncell; ++c) flag[c] = ray_total_[v][c] > 0 ? 2 : 0;
    bool any = false;
    for (std::size_t g = 0; g + 1 < groups_[v].size(); ++g) {
        const std::uint32_t c = lists_[v][groups_[v][g]].cell;
        float t = 0;
        bool kept_one = false;
        for (std::size_t k = groups_[v][g]; k < groups_[v][g + 1]; ++k)
            kept_one = kept_one || cur_[lists_[v][k].i] <= 0;
        flag[c] = kept_one ? 2 : 0;
        if (shortfall(v, g, &t)) flag[c] = 1, any = true, short_groups.push_back(g);
    }
    return any;
}

// A ball for each short line of sight of view v: about the kept voxel of its nearest covered
// line (`near`) nearest to the depth the field prefers, reaching the ray's `keep_` voxels
// nearest to that centre.
void Plausible::add_balls(std::size_t v, const std::vector<std::size_t>& short_groups,
                          const std::vector<std::uint32_t>& near, BallField& balls, double coarse) const {
    std::vector<char> anchor(near.size(), 0);
    for (std::size_t g : short_groups) {
        const std::uint32_t c = lists_[v][groups_[v][g]].cell;
        if (near[c] != kNone) anchor[near[c]] = 1;
    }
    const std::vector<Vox> anchors = kept_voxels_of(v, anchor);
    tbb::enumerable_thread_specific<std::vector<std::pair<openvdb::Vec3d, double>>> found;
    tbb::parallel_for(std::size_t(0), short_groups.size(), [&](std::size_t s) {
        const std::size_t g = short_groups[s];
        const auto rb = lists_[v].begin() + std::ptrdiff_t(groups_[v][g]),
                   re = lists_[v].begin() + std::ptrdiff_t(groups_[v][g + 1]);
        const std::uint32_t c = rb->cell;
        if (near[c] == kNone) return; // nothing kept in this view
        auto ab = std::lower_bound(anchors.begin(), anchors.end(), near[c],
                                   [](const Vox& a, std::uint32_t x) { return a.cell < x; });
        auto ae = ab;
        while (ae != anchors.end() && ae->cell == near[c]) ++ae;
        if (ab == ae) return;
        // The depth the field prefers: the ray's best voxel.
        const auto best = std::min_element(rb, re, [&](const Vox& a, const Vox& b) { return cur_[a.i] < cur_[b.i]; });
        const auto centre = std::min_element(
            ab, ae, [&](const Vox& a, const Vox& b) { return dist2(a.c, best->c) < dist2(b.c, best->c); });
        // The ray's `want` voxels nearest to the centre: the ball reaches the farthest.
        std::vector<double> d;
        for (auto it = rb; it != re; ++it) d.push_back(dist2(it->c, centre->c));
        const std::size_t want = std::min<std::size_t>(keep_, d.size());
        std::nth_element(d.begin(), d.begin() + std::ptrdiff_t(want - 1), d.end());
        const auto& o = centre->c;
        found.local().push_back({openvdb::Vec3d(o.x(), o.y(), o.z()), std::sqrt(d[want - 1]) + kMargin + 0.5 * coarse});
    });
    for (auto& f : found)
        for (const auto& [centre, radius] : f) balls.add(centre, radius);
}

// Smooth minimum of the field and the balls (never above either).
void Plausible::blend_balls(const BallField& balls) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vox_.nleaf), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t l = r.begin(); l != r.end(); ++l) {
            if (!balls.any_in(openvdb::CoordBBox::createCube(vox_.leaves.leaf(l).origin(), LeafT::DIM))) continue;
            std::size_t i = vox_.base[l];
            for (auto it = vox_.leaves.leaf(l).cbeginValueOn(); it; ++it, ++i) {
                const float b = balls.at(it.getCoord()), a = cur_[i];
                if (!(b < a + kBlend)) continue;
                const float h = std::clamp(0.5f + 0.5f * (a - b) / kBlend, 0.0f, 1.0f);
                cur_[i] = std::min(a, a + (b - a) * h - kBlend * h * (1.0f - h));
            }
        }
    });
}

// (d) Any line of sight still short keeps its best voxels.
void Plausible::keep_best() {
    for (std::size_t v = 0; v < nv_; ++v)
        for (std::size_t g = 0; g + 1 < groups_[v].size(); ++g) {
            float t = 0;
            if (!shortfall(v, g, &t)) continue;
            for (std::size_t k = groups_[v][g]; k < groups_[v][g + 1]; ++k)
                if (cur_[lists_[v][k].i] <= t) cur_[lists_[v][k].i] = std::min(cur_[lists_[v][k].i], -kMargin);
        }
}

} // namespace cm::plausible
