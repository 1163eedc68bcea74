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
#include "refine_lattice.h"
#include "refine_thin.h"

namespace cm {

namespace {

using namespace refining;
using BoolLeaf = openvdb::BoolTree::LeafNodeType;
using VecTree = openvdb::Vec3fTree;
using VecLeaf = VecTree::LeafNodeType;
using Word = std::uint64_t;

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
                                       const std::vector<Coord>& blocks, double total_work, const Progress& progress,
                                       std::size_t& n_cross_out, std::size_t& n_unresolved_out) {
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
        progress(double(c1) / total_work);
    }
    auto ctree = std::make_shared<VecTree>(kUnset);
    for (VecLeaf*& l : made)
        if (l) ctree->addLeaf(l), l = nullptr;
    n_cross_out = n_cross;
    n_unresolved_out = n_unresolved;
    return ctree;
}

} // namespace

void RefineOptions::declare(ParamBinder& b) {
    b.add_auto_on_off(thin, "thin",
                      "keep parts thinner than a cell (edges whose two outside ends pass through the hull); "
                      "auto: when a cell spans more than a pixel of the finest view");
}

void RefineStats::report(Metrics& m) const {
    m.count("crossings", crossings);
    m.count("thin_crossings", thin_crossings);
    m.metric("cell_px", cell_px);
    m.flag("thin_searched", thin_searched);
    m.warned_count("unresolved_crossings", unresolved,
                   "crossing(s) could not be placed from the silhouettes (the views differ from the ones carved?); "
                   "they sit at the grid point");
    m.count("grid_bytes", grid_bytes);
}

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

Result<std::shared_ptr<Volume>, RefineStats> refine(const Volume& in, std::shared_ptr<const Views> views,
                                                    const RefineOptions& opt, Progress progress) {
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
    // The input's silhouette tables when these are its views (the carving's), else new ones.
    const std::unique_ptr<VisualHull> hull_ptr = carved_hull(*in.occupancy, *views, carried_tables(in, views));
    const VisualHull& hull = *hull_ptr;
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
    out->silhouette_tables = hull.tables(); // for a stage that asks the views' hull again (dual_mc's normals)
    out->extra = in.extra;
    auto cgrid = openvdb::Vec3fGrid::create(ctree);
    cgrid->setTransform(in.occupancy->transform().copy());
    cgrid->setName("crossings");
    out->crossings = cgrid;

    const std::size_t n_thin =
        do_thin ? add_thin_parts(*out, *in.occupancy, hull, lat, blocks.size(), total_work, progress) : 0;
    if (opt.normals) add_normal_grids(*out, hull, opt.normal_px);
    progress(1.0);
    RefineStats st;
    st.crossings = n_cross;
    st.thin_crossings = n_thin;
    st.unresolved = n_unresolved;
    st.cell_px = cell_px;
    st.thin_searched = do_thin;
    st.grid_bytes = out->crossings->tree().memUsage();
    return {std::move(out), st};
}

} // namespace cm
