// hull.marching_intersections, the thin parts (refine_thin.h).
#include "refine_thin.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <memory>
#include <vector>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

namespace cm::refining {

namespace {

struct ThinHit {
    Coord p;
    int axis;
    float t0, t1;
};

// The lattice points whose edges the thin-part search covers: those of the clip box (one
// more on each side); without a clip box, the occupied region grown by a leaf.
openvdb::CoordBBox thin_region(const openvdb::BoolGrid& occupancy, const Lattice& lat, const Vec3d& clip_lo,
                               const Vec3d& clip_hi) {
    openvdb::CoordBBox region;
    occupancy.tree().evalActiveVoxelBoundingBox(region);
    region.expand(kDim);
    if (occupancy.getMetadata<openvdb::Vec3DMetadata>("hull_clip_min") &&
        occupancy.getMetadata<openvdb::Vec3DMetadata>("hull_clip_max")) {
        Coord lo, hi;
        for (int a = 0; a < 3; ++a) {
            lo[a] = int(std::floor((clip_lo[a] - lat.origin[a]) / lat.h)) - 1;
            hi[a] = int(std::ceil((clip_hi[a] - lat.origin[a]) / lat.h)) + 1;
        }
        region = openvdb::CoordBBox(lo, hi);
    }
    return region;
}

// The class (SilhouetteField::Class) of a lattice edge in each view seen along a world axis
// (orthographic, drop axis d), kept as it is first asked: such a view sees every edge along
// one line of the d axis alike (the projection ignores the d coordinate exactly), so the
// thin-part search, which asks about the same few thousand lines near each outline millions
// of times, classifies each line once. Answers are those of classify_segment itself.
class EdgeClasses {
public:
    // Lines whose other two coordinates lie in [lo, hi) (per axis); views whose tables would
    // pass kMaxEntries (a 4096^2 face of the region: 16 MB per edge axis) are left to
    // classify_segment.
    EdgeClasses(const VisualHull& hull, const Coord& lo, const Coord& hi) : lo_(lo) {
        constexpr std::size_t kMaxEntries = std::size_t(1) << 24;
        for (std::size_t i = 0; i < hull.size() && i < 64; ++i) {
            const int d = hull.field(i).drop_axis();
            if (d < 0) continue;
            View v;
            v.index = i;
            v.u = (d + 1) % 3;
            v.w = (d + 2) % 3;
            v.nw = std::size_t(hi[v.w] - lo[v.w]);
            const std::size_t n = std::size_t(hi[v.u] - lo[v.u]) * v.nw;
            if (n == 0 || n > kMaxEntries) continue;
            for (auto& t : v.table) t.assign(n, kUnknown);
            views_.push_back(std::move(v));
        }
    }
    // Whether a view of `mask` among those kept here sees the edge p -> p + e_a all outside.
    bool outside(const VisualHull& hull, const Lattice& lat, const Coord& p, int a, VisualHull::ViewMask mask) {
        for (auto& v : views_) {
            if (!((mask >> v.index) & 1u)) continue;
            signed char& slot =
                v.table[std::size_t(a)][std::size_t(p[v.u] - lo_[v.u]) * v.nw + std::size_t(p[v.w] - lo_[v.w])];
            std::atomic_ref<signed char> cell(slot);
            signed char c = cell.load(std::memory_order_relaxed);
            if (c == kUnknown) {
                Coord q = p;
                q[a] += 1;
                c = static_cast<signed char>(hull.field(v.index).classify_segment(lat.at(p), lat.at(q)));
                cell.store(c, std::memory_order_relaxed); // racing threads store the same answer
            }
            if (c == SilhouetteField::Outside) return true;
        }
        return false;
    }

private:
    static constexpr signed char kUnknown = 2;
    struct View {
        std::size_t index = 0;
        int u = 0, w = 0;                              ///< the two axes the view sees
        std::size_t nw = 0;                            ///< table row length (the w extent)
        std::array<std::vector<signed char>, 3> table; ///< per edge axis, by (u, w) of the edge's start
    };
    Coord lo_;
    std::vector<View> views_;
};

// Thin parts: edges whose two ends are outside but which pass through the hull. Blocks are
// decided hierarchically on the box their edges sweep ([o, o + n] in index space); only
// blocks the silhouettes cannot decide are tested edge by edge, and an edge a view along an
// axis already saw outside (EdgeClasses) is not tested again.
class ThinSearch {
public:
    ThinSearch(const VisualHull& hull, const Lattice& lat, EdgeClasses& classes)
        : hull_(hull), lat_(lat), classes_(classes) {}

    // The thin edges starting in the n^3 points at o, tested in the views of `mask`.
    void search(const OccAccessor& acc, const Coord& o, int n, VisualHull::ViewMask mask, double* flips,
                std::vector<ThinHit>& out, LineAnswers& lines) const {
        const auto c = hull_.classify(lat_.at(o), lat_.at(o.offsetBy(n)), mask);
        if (c != VisualHull::Class::Mixed) return; // all outside, or all inside (no outside ends)
        if (n > 4) {
            const int hn = n / 2;
            for (int k = 0; k < 8; ++k)
                search(acc, o.offsetBy((k & 4) ? hn : 0, (k & 2) ? hn : 0, (k & 1) ? hn : 0), hn, mask, flips, out,
                       lines);
            return;
        }
        // The views' answers by lines of the 8^3 block holding the leaf.
        const Coord block(o.x() & ~7, o.y() & ~7, o.z() & ~7);
        lines.new_block(block);
        // Occupancy of the (n + 1)^3 points the edges join, read once.
        constexpr int kSide = 5;
        bool in[kSide][kSide][kSide];
        for (int x = 0; x <= n; ++x)
            for (int y = 0; y <= n; ++y)
                for (int z = 0; z <= n; ++z) in[x][y][z] = acc.isValueOn(o.offsetBy(x, y, z));
        for (int x = 0; x < n; ++x)
            for (int y = 0; y < n; ++y)
                for (int z = 0; z < n; ++z) {
                    if (in[x][y][z]) continue;
                    const Coord p = o.offsetBy(x, y, z);
                    for (int a = 0; a < 3; ++a) {
                        if (in[x + (a == 0)][y + (a == 1)][z + (a == 2)]) continue;
                        if (classes_.outside(hull_, lat_, p, a, mask)) continue;
                        Coord q = p;
                        q[a] += 1;
                        const Vec3d wp = lat_.at(p), wq = lat_.at(q);
                        bool start = false;
                        const int nf = hull_.transitions(wp, wq, start, flips, 256, mask,
                                                         LineAnswers::Edge(lines, p - block, a, wp, wq));
                        if (nf < 2) continue;
                        // Inside intervals between the two outside ends; keep the longest.
                        double best0 = 0, best1 = 0;
                        bool cur = start;
                        double pos = 0;
                        for (int k = 0; k < nf; ++k) {
                            if (cur && flips[k] - pos > best1 - best0) best0 = pos, best1 = flips[k];
                            cur = !cur;
                            pos = flips[k];
                        }
                        if (best1 - best0 > 1e-6 && best0 > 0 && best1 < 1)
                            out.push_back({p, a, float(best0), float(best1)});
                    }
                }
    }

private:
    const VisualHull& hull_;
    const Lattice& lat_;
    EdgeClasses& classes_;
};

// The thin edges of `region`, in parallel over 64^3 tops; progress runs from
// nblocks / total_work to 2 nblocks / total_work.
std::vector<ThinHit> find_thin(const openvdb::BoolTree& occ, const VisualHull& hull, const Lattice& lat,
                               const openvdb::CoordBBox& region, std::size_t nblocks, double total_work,
                               const Progress& progress) {
    constexpr int kTop = 64;
    std::vector<Coord> tops;
    auto align = [](int v) { return int(std::floor(double(v) / kTop)) * kTop; };
    for (int x = align(region.min().x()); x <= region.max().x(); x += kTop)
        for (int y = align(region.min().y()); y <= region.max().y(); y += kTop)
            for (int z = align(region.min().z()); z <= region.max().z(); z += kTop) tops.emplace_back(x, y, z);
    if (tops.empty()) return {};
    // The edges start in the tops' points.
    const Coord first(align(region.min().x()), align(region.min().y()), align(region.min().z()));
    EdgeClasses classes(hull, first, tops.back().offsetBy(kTop));
    const ThinSearch search(hull, lat, classes);
    tbb::enumerable_thread_specific<std::vector<ThinHit>> hits;
    const std::size_t tchunk = std::max<std::size_t>(1, tops.size() / 50);
    for (std::size_t c0 = 0; c0 < tops.size(); c0 += tchunk) {
        const std::size_t c1 = std::min(tops.size(), c0 + tchunk);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(c0, c1, 1), [&](const tbb::blocked_range<std::size_t>& r) {
            OccAccessor acc(occ);
            auto& mine = hits.local();
            const auto lines = std::make_unique<LineAnswers>(hull);
            double flips[256];
            for (std::size_t i = r.begin(); i < r.end(); ++i)
                search.search(acc, tops[i], kTop, VisualHull::kAllViews, flips, mine, *lines);
        });
        progress((double(nblocks) + double(nblocks) * double(c1) / tops.size()) / total_work);
    }
    std::vector<ThinHit> all;
    for (auto& v : hits) all.insert(all.end(), v.begin(), v.end());
    return all;
}

// The thin edges as the grids "thin_enter" and "thin_leave" of `out` (replacing any it had):
// per lattice point and axis, where its edge's inside interval starts and ends.
void add_thin_grids(Volume& out, const std::vector<ThinHit>& all, const openvdb::math::Transform& xform) {
    auto enter = openvdb::Vec3fGrid::create(kUnset), leave = openvdb::Vec3fGrid::create(kUnset);
    auto ea = enter->getAccessor();
    auto la = leave->getAccessor();
    for (const ThinHit& t : all) {
        openvdb::Vec3f e = ea.isValueOn(t.p) ? ea.getValue(t.p) : kUnset;
        openvdb::Vec3f l = la.isValueOn(t.p) ? la.getValue(t.p) : kUnset;
        e[t.axis] = t.t0;
        l[t.axis] = t.t1;
        ea.setValueOn(t.p, e);
        la.setValueOn(t.p, l);
    }
    for (auto& g : {enter, leave}) g->setTransform(xform.copy());
    enter->setName("thin_enter");
    leave->setName("thin_leave");
    // Replace any previous thin grids.
    std::erase_if(out.extra, [](const openvdb::GridBase::Ptr& g) {
        return g && (g->getName() == "thin_enter" || g->getName() == "thin_leave");
    });
    out.extra.push_back(enter);
    out.extra.push_back(leave);
}

} // namespace

std::size_t add_thin_parts(Volume& out, const openvdb::BoolGrid& occupancy, const VisualHull& hull, const Lattice& lat,
                           std::size_t nblocks, double total_work, const Progress& progress) {
    const openvdb::CoordBBox region = thin_region(occupancy, lat, hull.clip_lo(), hull.clip_hi());
    const std::vector<ThinHit> all = find_thin(occupancy.tree(), hull, lat, region, nblocks, total_work, progress);
    if (!all.empty()) add_thin_grids(out, all, occupancy.transform());
    return all.size();
}

} // namespace cm::refining
