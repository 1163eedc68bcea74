#include "refine.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>

#include <openvdb/tree/LeafManager.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "geometry/carved_hull.h"
#include "geometry/hull_normal.h"
#include "geometry/visual_hull.h"

namespace cm {

namespace {

using Coord = openvdb::Coord;
using BoolLeaf = openvdb::BoolTree::LeafNodeType;
using VecTree = openvdb::Vec3fTree;
using VecLeaf = VecTree::LeafNodeType;
using Word = std::uint64_t;
using OccAccessor = openvdb::tree::ValueAccessor<const openvdb::BoolTree>;
constexpr int kDim = 8;
const openvdb::Vec3f kUnset(-1.f, -1.f, -1.f);

// Occupancy of one 8^3 block as 8 words (word x, bit 8 y + z), as in OpenVDB's leaf masks.
using BlockBits = std::array<Word, 8>;

BlockBits block_bits(const OccAccessor& acc, const Coord& origin) {
    BlockBits b;
    if (const BoolLeaf* leaf = acc.probeConstLeaf(origin)) {
        for (int x = 0; x < 8; ++x) b[x] = leaf->getValueMask().getWord<Word>(x);
    } else {
        b.fill(acc.isValueOn(origin) ? ~Word(0) : Word(0));
    }
    return b;
}

struct Lattice {
    Vec3d origin;
    double h = 1;
    Vec3d at(const Coord& c) const { return {origin.x + h * c.x(), origin.y + h * c.y(), origin.z + h * c.z()}; }
};

// Per axis, the bits of the block where the edge p -> p + e_a joins differing occupancy.
void edge_diffs(const BlockBits& w, const BlockBits& nx, const BlockBits& ny, const BlockBits& nz,
                std::array<BlockBits, 3>& d) {
    constexpr Word kZ7 = 0x7f7f7f7f7f7f7f7fULL; // bits with z != 7
    constexpr Word kZ0 = 0x0101010101010101ULL; // bits with z == 0
    for (int x = 0; x < 8; ++x) {
        const Word wx = w[x];
        d[0][x] = wx ^ (x < 7 ? w[x + 1] : nx[0]);
        d[1][x] = ((wx ^ (wx >> 8)) & 0x00ffffffffffffffULL) | ((((wx >> 56) ^ ny[x]) & 0xffULL) << 56);
        d[2][x] = ((wx ^ (wx >> 1)) & kZ7) | ((((wx >> 7) ^ nz[x]) & kZ0) << 7);
    }
}

struct ThinHit {
    Coord p;
    int axis;
    float t0, t1;
};

// Blocks that can hold a crossing: every occupancy leaf and its -x, -y, -z neighbours (an
// outside point there may have an inside neighbour in the leaf). Tiles never touch the
// outside (volume.h), so no other block can hold one.
// A neighbour block that is not a leaf itself is constant; it needs a leaf only when it is
// outside and the leaf's face towards it has inside voxels. Sorted, each once.
std::vector<Coord> crossing_blocks(const openvdb::BoolTree& occ) {
    std::vector<Coord> blocks;
    OccAccessor acc(occ);
    for (auto it = occ.cbeginLeaf(); it; ++it) {
        const Coord o = it->origin();
        blocks.push_back(o);
        const auto& m = it->getValueMask();
        Word face[3] = {m.getWord<Word>(0), 0, 0};
        for (int x = 0; x < 8; ++x) {
            face[1] |= m.getWord<Word>(x) & 0xffULL;
            face[2] |= m.getWord<Word>(x) & 0x0101010101010101ULL;
        }
        for (int a = 0; a < 3; ++a) {
            Coord n = o;
            n[a] -= kDim;
            if (!face[a] || acc.probeConstLeaf(n) || acc.isValueOn(n)) continue;
            blocks.push_back(n);
        }
    }
    std::sort(blocks.begin(), blocks.end());
    blocks.erase(std::unique(blocks.begin(), blocks.end()), blocks.end());
    return blocks;
}

// Grid spacing in pixels of the finest view, at the centre of the hull.
double cell_pixels(const openvdb::BoolTree& occ, const Lattice& lat, const VisualHull& hull) {
    openvdb::CoordBBox bb;
    occ.evalActiveVoxelBoundingBox(bb);
    const Vec3d centre = (lat.at(bb.min()) + lat.at(bb.max())) * 0.5;
    double finest = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < hull.size(); ++i) finest = std::min(finest, hull.field(i).pixel_size_at(centre));
    return lat.h / finest;
}

// What the views seen along a world axis (orthographic, drop axis d) said about the edges of
// 8^3 blocks. Such a view sees every edge along one line of the d axis alike (its projection
// ignores the d coordinate exactly), and on the part of the hull that view carves (a cone
// extruded along d) the edges of a line cross it alike too: the view's class, start and flips
// for a line are found once and given again to the line's other edges, in the block and in
// the blocks after it along d (a thread takes the blocks in order). Answers are those of the
// view itself, so the crossings are the same.
class LineAnswers {
public:
    explicit LineAnswers(const VisualHull& hull) : hull_(hull), slot_(hull.size(), -1) {
        for (std::size_t i = 0; i < hull.size() && i < 64 && kept_ < kViews; ++i)
            if (const int d = hull.field(i).drop_axis(); d >= 0) {
                drop_[kept_] = d;
                slot_[i] = kept_++;
            }
    }
    // The block at `o` comes next: a view keeps its answers when the block lies on the same
    // lines as the last one (the next block along the view's axis), and forgets them otherwise.
    void new_block(const Coord& o) {
        for (int s = 0; s < kept_; ++s) {
            const int d = drop_[s], u = (d + 1) % 3, w = (d + 2) % 3;
            if (has_[s] && at_[s][0] == o[u] && at_[s][1] == o[w]) continue;
            std::fill_n(known_ + s * kPerView, kPerView, std::uint8_t(0));
            has_[s] = true;
            at_[s][0] = o[u];
            at_[s][1] = o[w];
        }
    }

    // The views' answers about the edge from `p` (the block's local coordinates, 0 to 7) along
    // axis `a`, whose ends are the world points `wa` and `wb`.
    class Edge {
    public:
        Edge(LineAnswers& cache, const Coord& p, int a, const Vec3d& wa, const Vec3d& wb)
            : c_(cache), p_(p), a_(a), wa_(wa), wb_(wb) {}
        SilhouetteField::Class classify(std::size_t i) const {
            const int k = entry(i);
            if (k < 0) return c_.hull_.field(i).classify_segment(wa_, wb_);
            if (!(c_.known_[k] & kClass)) {
                c_.class_[k] = static_cast<signed char>(c_.hull_.field(i).classify_segment(wa_, wb_));
                c_.known_[k] |= kClass;
            }
            return static_cast<SilhouetteField::Class>(c_.class_[k]);
        }
        int transitions(std::size_t i, bool& st, double* out, int max) const {
            const int k = entry(i);
            if (k >= 0 && (c_.known_[k] & kFlips) && c_.count_[k] < max) {
                st = c_.start_[k] != 0;
                std::copy_n(c_.flips_[k], c_.count_[k], out);
                return c_.count_[k];
            }
            const int n = c_.hull_.field(i).transitions(wa_, wb_, st, out, max);
            if (k >= 0 && n <= kKeep && n < max) {
                c_.start_[k] = st;
                c_.count_[k] = static_cast<std::uint8_t>(n);
                std::copy_n(out, n, c_.flips_[k]);
                c_.known_[k] |= kFlips;
            }
            return n;
        }

    private:
        // The entry of view i's line through the edge, or -1 for a view asked every time.
        int entry(std::size_t i) const {
            const int s = c_.slot_[i];
            if (s < 0) return -1;
            const int d = c_.drop_[s];
            return ((s * 3 + a_) * 8 + p_[(d + 1) % 3]) * 8 + p_[(d + 2) % 3];
        }
        LineAnswers& c_;
        const Coord p_;
        const int a_;
        const Vec3d &wa_, &wb_;
    };

private:
    static constexpr int kViews = 8; ///< views kept per block (more are asked every time)
    static constexpr int kKeep = 6;  ///< flips kept per line (a line with more is asked again)
    static constexpr int kPerView = 3 * 64;
    static constexpr int kEntries = kViews * kPerView;
    static constexpr std::uint8_t kClass = 1, kFlips = 2;
    const VisualHull& hull_;
    std::vector<int> slot_; ///< per view: its place among the kept views, or -1
    int kept_ = 0;
    int drop_[kViews] = {};
    bool has_[kViews] = {};  ///< whether the view's entries are of some block's lines
    int at_[kViews][2] = {}; ///< those lines' block coordinates
    std::uint8_t known_[kEntries];
    signed char class_[kEntries];
    std::uint8_t start_[kEntries], count_[kEntries];
    double flips_[kEntries][kKeep];
};

// The crossing of each edge whose ends differ in occupancy, found in the views.
class CrossingFinder {
public:
    CrossingFinder(const VisualHull& hull, const Lattice& lat) : hull_(hull), lat_(lat) {
        // A view along axis a sees an a-edge as one point: when one end is inside every view,
        // so is the whole edge in that view, and it can be left out of the edge's test.
        for (std::size_t i = 0; i < hull.size() && i < 64; ++i)
            if (const int k = hull.field(i).drop_axis(); k >= 0) along_[k] |= VisualHull::ViewMask(1) << i;
    }

    // The crossings of the edges starting in the block at o, into `leaf` (made at the first
    // crossing); counts the crossings and those the views could not place.
    void block(const OccAccessor& acc, const Coord& o, VecLeaf*& leaf, std::size_t& cross, std::size_t& unresolved,
               LineAnswers& lines) const {
        double flips[256];
        lines.new_block(o);
        std::array<BlockBits, 3> diff;
        const BlockBits w = block_bits(acc, o);
        edge_diffs(w, block_bits(acc, o.offsetBy(kDim, 0, 0)), block_bits(acc, o.offsetBy(0, kDim, 0)),
                   block_bits(acc, o.offsetBy(0, 0, kDim)), diff);
        // Views that see the whole block (with its edges) inside need no test.
        VisualHull::ViewMask mask = VisualHull::kAllViews;
        hull_.classify(lat_.at(o), lat_.at(o.offsetBy(kDim)), mask);
        for (int a = 0; a < 3; ++a)
            for (int x = 0; x < 8; ++x) {
                Word bits = diff[a][x];
                while (bits) {
                    const int b = __builtin_ctzll(bits);
                    bits &= bits - 1;
                    const Coord p = o.offsetBy(x, b >> 3, b & 7);
                    Coord q = p;
                    q[a] += 1;
                    const bool p_in = (w[x] >> b) & 1u;
                    bool start = false;
                    const Vec3d wp = lat_.at(p), wq = lat_.at(q);
                    const int nf = hull_.transitions(wp, wq, start, flips, 256, mask & ~along_[a],
                                                     LineAnswers::Edge(lines, Coord(x, b >> 3, b & 7), a, wp, wq));
                    double t;
                    if (p_in) {
                        // Where the inside end's solid stops: the first flip to outside.
                        if (start && nf > 0) t = flips[0];
                        else t = start ? 1.0 : 0.0, ++unresolved;
                    } else {
                        // Where the solid that reaches q starts: the last flip to inside.
                        const bool end_in = start != (nf % 2 == 1);
                        if (end_in && nf > 0) t = flips[nf - 1];
                        else t = end_in ? 0.0 : 1.0, ++unresolved;
                    }
                    if (!leaf) leaf = new VecLeaf(o, kUnset, false);
                    const openvdb::Index off = VecLeaf::coordToOffset(p);
                    openvdb::Vec3f v = leaf->isValueOn(off) ? leaf->getValue(off) : kUnset;
                    v[a] = float(std::clamp(t, 0.0, 1.0));
                    leaf->setValueOn(off, v);
                    ++cross;
                }
            }
    }

    const VisualHull& hull() const { return hull_; }

private:
    const VisualHull& hull_;
    const Lattice& lat_;
    VisualHull::ViewMask along_[3] = {0, 0, 0};
};

// The crossings of every block, in parallel; progress runs to blocks.size() / total_work.
std::shared_ptr<VecTree> crossing_tree(const openvdb::BoolTree& occ, const CrossingFinder& finder,
                                       const std::vector<Coord>& blocks, double total_work,
                                       const std::function<void(double)>& progress, std::size_t& n_cross_out,
                                       std::size_t& n_unresolved_out) {
    // Leaves are made (in parallel) only for blocks that get a crossing, then linked in.
    std::vector<VecLeaf*> made(blocks.size(), nullptr);
    struct LeafGuard {
        std::vector<VecLeaf*>& v;
        ~LeafGuard() {
            for (VecLeaf* l : v) delete l;
        }
    } guard{made};

    std::atomic<std::size_t> n_cross{0}, n_unresolved{0};
    const std::size_t chunk = std::max<std::size_t>(256, blocks.size() / 50);
    for (std::size_t c0 = 0; c0 < blocks.size(); c0 += chunk) {
        const std::size_t c1 = std::min(blocks.size(), c0 + chunk);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(c0, c1, 16), [&](const tbb::blocked_range<std::size_t>& r) {
            OccAccessor acc(occ);
            const auto lines = std::make_unique<LineAnswers>(finder.hull());
            std::size_t cross = 0, unresolved = 0;
            for (std::size_t li = r.begin(); li < r.end(); ++li)
                finder.block(acc, blocks[li], made[li], cross, unresolved, *lines);
            n_cross += cross;
            n_unresolved += unresolved;
        });
        if (progress) progress(double(c1) / total_work);
    }
    auto ctree = std::make_shared<VecTree>(kUnset);
    for (VecLeaf*& l : made)
        if (l) ctree->addLeaf(l), l = nullptr;
    n_cross_out = n_cross;
    n_unresolved_out = n_unresolved;
    return ctree;
}

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
                               const std::function<void(double)>& progress) {
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
        if (progress) progress((double(nblocks) + double(nblocks) * double(c1) / tops.size()) / total_work);
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

void add_normal_grids(Volume& vol, const VisualHull& hull, double normal_px) {
    if (!vol.crossings) throw Error("the volume has no crossings to give normals to");
    const auto& xform = vol.crossings->transform();
    std::erase_if(vol.extra, [](const openvdb::GridBase::Ptr& g) {
        return g && (g->getName() == "normal_x" || g->getName() == "normal_y" || g->getName() == "normal_z");
    });
    const char* names[3] = {"normal_x", "normal_y", "normal_z"};
    for (int a = 0; a < 3; ++a) {
        auto tree = std::make_shared<VecTree>(vol.crossings->tree(), openvdb::Vec3f(0.0f), openvdb::TopologyCopy());
        openvdb::tree::LeafManager<VecTree> leaves(*tree);
        const VecTree& ctree = vol.crossings->tree();
        leaves.foreach ([&](VecLeaf& leaf, std::size_t) {
            const VecLeaf* cl = ctree.probeConstLeaf(leaf.origin());
            for (auto it = leaf.beginValueOn(); it; ++it) {
                const float t = cl ? cl->getValue(it.pos())[a] : -1.0f;
                if (!(t >= 0.0f && t <= 1.0f)) {
                    it.setValueOff();
                    continue;
                }
                openvdb::Vec3d ip = it.getCoord().asVec3d();
                ip[a] += double(t);
                const openvdb::Vec3d w = xform.indexToWorld(ip);
                const Vec3d n = hull_normal(hull, {w.x(), w.y(), w.z()}, normal_px).normal;
                it.setValue(openvdb::Vec3f(float(n.x), float(n.y), float(n.z)));
            }
        });
        tree->prune();
        auto grid = openvdb::Vec3fGrid::create(tree);
        grid->setTransform(xform.copy());
        grid->setName(names[a]);
        vol.extra.push_back(grid);
    }
}

std::shared_ptr<Volume> refine(const Volume& in, std::shared_ptr<const Views> views, const RefineOptions& opt,
                               const std::function<void(double)>& progress, RefineStats* stats) {
    if (!in.occupancy) throw Error("the volume has no occupancy grid");
    if (!views) views = in.views;
    if (!views || views->views.empty()) throw Error("no views: the crossings are found from the views' silhouettes");
    const auto& xform = in.occupancy->transform();
    if (!xform.isLinear() || !xform.hasUniformScale())
        throw Error("the volume's transform is not a uniform linear transform");
    Lattice lat;
    {
        const openvdb::Vec3d o = xform.indexToWorld(openvdb::Vec3d(0, 0, 0));
        lat.origin = {o.x(), o.y(), o.z()};
        lat.h = xform.voxelSize()[0];
    }
    const std::unique_ptr<VisualHull> hull_ptr = carved_hull(*in.occupancy, *views);
    const VisualHull& hull = *hull_ptr;
    const Vec3d clip_lo = hull.clip_lo(), clip_hi = hull.clip_hi();
    const openvdb::BoolTree& occ = in.occupancy->tree();

    // Topology of the crossings.
    const std::vector<Coord> blocks = crossing_blocks(occ);
    const CrossingFinder finder(hull, lat);
    const double cell_px = cell_pixels(occ, lat, hull);
    const bool do_thin =
        opt.thin == RefineOptions::Thin::On || (opt.thin == RefineOptions::Thin::Auto && cell_px > opt.thin_auto_px);
    const double total_work = double(blocks.size()) * (do_thin ? 2.0 : 1.0) + 1.0;
    std::size_t n_cross = 0, n_unresolved = 0;
    auto ctree = crossing_tree(occ, finder, blocks, total_work, progress, n_cross, n_unresolved);

    auto out = std::make_shared<Volume>();
    out->occupancy = in.occupancy;
    out->views = views;
    out->view_data = hull.tables(); // for a stage that reads the views' hull again (dual_mc's normals)
    out->extra = in.extra;
    auto cgrid = openvdb::Vec3fGrid::create(ctree);
    cgrid->setTransform(in.occupancy->transform().copy());
    cgrid->setName("crossings");
    out->crossings = cgrid;

    std::size_t n_thin = 0;
    if (do_thin) {
        const openvdb::CoordBBox region = thin_region(*in.occupancy, lat, clip_lo, clip_hi);
        const std::vector<ThinHit> all = find_thin(occ, hull, lat, region, blocks.size(), total_work, progress);
        if (!all.empty()) add_thin_grids(*out, all, in.occupancy->transform());
        n_thin = all.size();
    }
    if (opt.normals) add_normal_grids(*out, hull, opt.normal_px);
    if (progress) progress(1.0);
    if (stats) {
        stats->crossings = n_cross;
        stats->thin_crossings = n_thin;
        stats->unresolved = n_unresolved;
        stats->cell_px = cell_px;
        stats->thin_searched = do_thin;
    }
    return out;
}

} // namespace cm
