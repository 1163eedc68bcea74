// Marching Cubes on a sparse BoolGrid, in 8^3 blocks of cells.
//
// 1. Candidate blocks: around every leaf of the occupancy (and of the thin-part grid),
//    plus the shell of any active tile that touches non-solid space. A block is kept when
//    one of its cells has mixed corners. Each block keeps its 9^3 corner states as bit rows.
// 2. Vertices: one per crossed lattice edge, owned by the block holding the edge's start
//    point, numbered block by block (axis, x, then y-z bit order), so a cell finds the
//    index of any of its edges by a popcount in the owning block: no hash, no locks.
// 3. Triangles: counted per block, then written at the block's offset. Ambiguous faces
//    are resolved from the four crossing positions, which both cells sharing the face read
//    identically, so the two sides always pair the crossings the same way.
#include "marching_cubes.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <limits>
#include <map>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include "core/error.h"
#include "mc_table.h"

namespace cm {
namespace {

using openvdb::Coord;
using FlipGrid = openvdb::Vec3fGrid;
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
constexpr std::int64_t kBias = std::int64_t(1) << 20;   // block coordinates are stored in 21 bits

std::uint64_t block_key(const Coord& o) {
    return (std::uint64_t((o.x() >> 3) + kBias) << 42) | (std::uint64_t((o.y() >> 3) + kBias) << 21) |
           std::uint64_t((o.z() >> 3) + kBias);
}
Coord key_origin(std::uint64_t k) {
    const std::uint64_t m = (std::uint64_t(1) << 21) - 1;
    return Coord(int((std::int64_t((k >> 42) & m) - kBias) * 8), int((std::int64_t((k >> 21) & m) - kBias) * 8),
                 int((std::int64_t(k & m) - kBias) * 8));
}

struct Block {
    Coord origin;
    std::uint16_t rows[9][9];        ///< bit z of rows[x][y]: corner (x, y, z) is inside
    std::uint64_t cross[3][8];       ///< bit 8y+z of cross[a][x]: edge (x,y,z) -> +a is crossed
    std::uint16_t pre[3][8];         ///< vertices of this block before cross[a][x]
    std::uint32_t nb[8];             ///< the blocks at origin + 8 (dx, dy, dz), index dx | dy<<1 | dz<<2
    std::uint32_t vbase = 0, nverts = 0;
    std::uint32_t tbase = 0, ntris = 0;
    std::uint32_t xbase = 0, nextra = 0;
};

/// Corner states of the lattice: occupancy, plus points made inside to keep thin parts.
class States {
public:
    States(const openvdb::BoolGrid& occ, const FlipGrid* flips) : occ_(occ), flips_(flips) {}

    /// Inside bits of the 8 leaf-sized regions at origin + 8 (dx, dy, dz), as leaf words:
    /// word x of region d holds bit 8y+z.
    void load(const Coord& origin, std::uint64_t words[8][8]) const {
        auto acc = occ_.getConstUnsafeAccessor();   // per call, so no registration with the tree
        for (int d = 0; d < 8; ++d) {
            const Coord o = origin.offsetBy(8 * (d & 1), 8 * ((d >> 1) & 1), 8 * ((d >> 2) & 1));
            if (const auto* leaf = acc.probeConstLeaf(o)) {
                const auto& mask = leaf->getValueMask();
                const std::uint64_t* data = leaf->buffer().data();
                for (int x = 0; x < 8; ++x) words[d][x] = mask.getWord<std::uint64_t>(openvdb::Index(x)) & data[x];
            } else {
                bool v = false;
                const bool on = acc.probeValue(o, v);
                const std::uint64_t fill = (on && v) ? ~std::uint64_t(0) : 0;
                for (int x = 0; x < 8; ++x) words[d][x] = fill;
            }
        }
        if (!flips_) return;
        auto facc = flips_->getConstUnsafeAccessor();
        for (int d = 0; d < 8; ++d) {
            const Coord o = origin.offsetBy(8 * (d & 1), 8 * ((d >> 1) & 1), 8 * ((d >> 2) & 1));
            if (const auto* leaf = facc.probeConstLeaf(o)) {
                const auto& mask = leaf->getValueMask();
                for (int x = 0; x < 8; ++x) words[d][x] |= mask.getWord<std::uint64_t>(openvdb::Index(x));
            }
        }
    }

    /// Fills the 9^3 corner rows of the block at `origin`; returns true when a cell is mixed.
    bool fill(const Coord& origin, std::uint16_t rows[9][9]) const {
        std::uint64_t w[8][8];
        load(origin, w);
        for (int x = 0; x < 9; ++x)
            for (int y = 0; y < 9; ++y) {
                const int d = (x >> 3) | ((y >> 3) << 1);
                const int lx = x & 7, sh = 8 * (y & 7);
                rows[x][y] = std::uint16_t(((w[d][lx] >> sh) & 0xFF) | (((w[d | 4][lx] >> sh) & 1) << 8));
            }
        for (int x = 0; x < 8; ++x)
            for (int y = 0; y < 8; ++y)
                if (mixed_row(rows, x, y)) return true;
        return false;
    }

    static unsigned mixed_row(const std::uint16_t rows[9][9], int x, int y) {
        const unsigned r0 = rows[x][y], r1 = rows[x][y + 1], r2 = rows[x + 1][y], r3 = rows[x + 1][y + 1];
        const unsigned all = r0 & r1 & r2 & r3, any = r0 | r1 | r2 | r3;
        return ((any | (any >> 1)) & ~(all & (all >> 1))) & 0xFFu;
    }

private:
    const openvdb::BoolGrid& occ_;
    const FlipGrid* flips_;
};

/// Population count without a library call (the build does not assume the POPCNT instruction).
inline unsigned popcount64(std::uint64_t x) {
    x = x - ((x >> 1) & 0x5555555555555555ull);
    x = (x & 0x3333333333333333ull) + ((x >> 2) & 0x3333333333333333ull);
    x = (x + (x >> 4)) & 0x0F0F0F0F0F0F0F0Full;
    return unsigned((x * 0x0101010101010101ull) >> 56);
}

/// True when both transforms put the grid points at the same places.
bool same_lattice(const openvdb::math::Transform& a, const openvdb::math::Transform& b) {
    const double tol = 1e-9 * std::max(1.0, a.voxelSize()[0]);
    for (const openvdb::Vec3d p : {openvdb::Vec3d(0, 0, 0), openvdb::Vec3d(1, 0, 0), openvdb::Vec3d(0, 1, 0), openvdb::Vec3d(0, 0, 1)})
        if ((a.indexToWorld(p) - b.indexToWorld(p)).length() > tol) return false;
    return true;
}

/// Runs fn(i) for i in [0, n) in parallel chunks, reporting progress between chunks.
template <typename Fn>
void for_blocks(std::size_t n, double p0, double p1, const MarchingCubesOptions& opt, Fn&& fn) {
    const std::size_t chunk = 4096;
    for (std::size_t start = 0; start < n; start += chunk) {
        const std::size_t end = std::min(n, start + chunk);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(start, end, 16), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) fn(i);
        });
        if (opt.progress) opt.progress(p0 + (p1 - p0) * double(end) / double(n));
    }
}

/// Points made inside so that thin parts (inside intervals on edges whose ends are both
/// outside) survive: for each such edge, its end nearer to the interval. The value is the
/// offset (in cells, per axis) from the point to the near face of its thin part: vertices on
/// the point's other edges, about which nothing is known, are moved there so the part keeps
/// its thickness instead of reaching back to the grid point.
/// An edge next to the resolved solid (a cell around it has an inside corner) is most often
/// the body's own surface bulging between two grid points, which the body's surface already
/// covers to within the cell; promoting a point there would raise a spike. Such edges are
/// promoted only when they link a thin part found away from the solid back to it (26-connected
/// to a promoted point), so a finger thinner than a cell stays attached to its hand.
FlipGrid::Ptr promote_thin(const Volume& vol, const openvdb::Vec3fGrid& enter, const openvdb::Vec3fGrid& leave,
                            std::size_t& count) {
    auto flips = FlipGrid::create(openvdb::Vec3f(0.0f));
    flips->setTransform(vol.occupancy->transform().copy());
    auto facc = flips->getAccessor();
    auto oacc = vol.occupancy->getConstAccessor();
    auto lacc = leave.getConstAccessor();
    auto promote = [&](const Coord& q, const openvdb::Vec3f& offset) {
        openvdb::Vec3f o = facc.getValue(q);
        if (!facc.isValueOn(q)) ++count;
        for (int a = 0; a < 3; ++a)
            if (offset[a] != 0.0f) o[a] = offset[a];
        facc.setValueOn(q, o);
    };
    std::map<Coord, openvdb::Vec3f> near;   // candidate point -> offset, for edges next to the solid
    std::vector<Coord> frontier;
    for (auto it = enter.cbeginValueOn(); it; ++it) {
        if (!it.isVoxelValue()) continue;
        const Coord p = it.getCoord();
        const openvdb::Vec3f t0 = *it, t1 = lacc.getValue(p);
        for (int a = 0; a < 3; ++a) {
            if (!(t0[a] >= 0.0f && t1[a] <= 1.0f && t0[a] < t1[a])) continue;
            Coord q = p;
            openvdb::Vec3f offset(0.0f);
            if (t0[a] > 1.0f - t1[a]) {
                q[a] += 1;
                offset[a] = t1[a] - 1.0f;
            } else {
                offset[a] = t0[a];
            }
            bool v = false;
            if (oacc.probeValue(q, v) && v) continue;   // inside already (not expected)
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            bool near_solid = false;
            for (int i = 0; i < 18 && !near_solid; ++i) {
                Coord r = p;
                r[a] += i & 1;
                r[b] += (i >> 1) % 3 - 1;
                r[c] += (i >> 1) / 3 - 1;
                near_solid = oacc.probeValue(r, v) && v;
            }
            if (near_solid) {
                near[q][a] = offset[a];
            } else {
                promote(q, offset);
                frontier.push_back(q);
            }
        }
    }
    while (!frontier.empty()) {
        const Coord q = frontier.back();
        frontier.pop_back();
        for (int d = 0; d < 27; ++d) {
            const Coord r = q.offsetBy(d % 3 - 1, (d / 3) % 3 - 1, d / 9 - 1);
            const auto it = near.find(r);
            if (it == near.end()) continue;
            promote(r, it->second);
            near.erase(it);
            frontier.push_back(r);
        }
    }
    return flips;
}

} // namespace

Mesh marching_cubes(const Volume& vol, const MarchingCubesOptions& opt, MarchingCubesStats* stats_out) {
    if (!vol.occupancy) throw Error("the volume has no occupancy grid");
    const openvdb::BoolGrid& occ = *vol.occupancy;
    const auto& xform = occ.transform();
    const mc::Table& table = mc::Table::get();
    MarchingCubesStats stats;

    const openvdb::Vec3fGrid* crossings = (opt.use_crossings && vol.crossings) ? vol.crossings.get() : nullptr;
    if (crossings && !same_lattice(crossings->transform(), xform))
        throw Error("the crossings grid is not on the occupancy's transform");
    const openvdb::Vec3fGrid *thin_enter = nullptr, *thin_leave = nullptr;
    if (opt.use_thin) {
        thin_enter = dynamic_cast<const openvdb::Vec3fGrid*>(vol.find_extra("thin_enter").get());
        thin_leave = dynamic_cast<const openvdb::Vec3fGrid*>(vol.find_extra("thin_leave").get());
        if (!thin_enter || !thin_leave) thin_enter = thin_leave = nullptr;
        if (thin_enter && (!same_lattice(thin_enter->transform(), xform) || !same_lattice(thin_leave->transform(), xform)))
            throw Error("the thin-part grids are not on the occupancy's transform");
    }
    FlipGrid::Ptr flips;
    if (thin_enter) {
        flips = promote_thin(vol, *thin_enter, *thin_leave, stats.thin_points);
        if (flips->tree().empty()) flips.reset();
    }

    const openvdb::CoordBBox bbox = occ.evalActiveVoxelBoundingBox();
    const int limit = int(kBias) * 8 - 16;
    for (int a = 0; a < 3; ++a)
        if (!occ.tree().empty() && (bbox.min()[a] < -limit || bbox.max()[a] > limit))
            throw Error("the occupancy grid spans more than " + std::to_string(limit) + " voxels from the origin");

    // 1. Candidate blocks.
    std::vector<std::uint64_t> keys;
    auto add_around = [&](const Coord& o) {
        for (int d = 0; d < 8; ++d) keys.push_back(block_key(o.offsetBy(-8 * (d & 1), -8 * ((d >> 1) & 1), -8 * ((d >> 2) & 1))));
    };
    for (auto it = occ.tree().cbeginLeaf(); it; ++it) add_around(it->origin());
    if (flips)
        for (auto it = flips->tree().cbeginLeaf(); it; ++it) add_around(it->origin());
    {
        auto acc = occ.getConstAccessor();
        for (auto it = occ.tree().cbeginValueOn(); it; ++it) {
            if (it.isVoxelValue() || !*it) continue;
            const openvdb::CoordBBox tile = it.getBoundingBox();
            const int s = tile.dim().x(), level = int(it.getLevel());
            bool surrounded = true;
            for (int d = 0; d < 27 && surrounded; ++d) {
                if (d == 13) continue;
                const Coord o = tile.min().offsetBy(s * (d % 3 - 1), s * ((d / 3) % 3 - 1), s * (d / 9 - 1));
                bool v = false;
                // A value stored at this tile's level or above covers the whole neighbour region.
                surrounded = acc.probeValue(o, v) && v && acc.getValueDepth(o) >= 0 &&
                             int(openvdb::BoolTree::DEPTH) - 1 - acc.getValueDepth(o) >= level;
            }
            if (surrounded) continue;
            const Coord lo = tile.min().offsetBy(-8), hi = tile.max().offsetBy(1 - 8);
            for (int x = lo.x(); x <= hi.x(); x += 8) {
                const bool bx = x == lo.x() || x == hi.x();
                for (int y = lo.y(); y <= hi.y(); y += 8) {
                    const bool by = y == lo.y() || y == hi.y();
                    if (bx || by) {
                        for (int z = lo.z(); z <= hi.z(); z += 8) keys.push_back(block_key(Coord(x, y, z)));
                    } else {
                        keys.push_back(block_key(Coord(x, y, lo.z())));
                        keys.push_back(block_key(Coord(x, y, hi.z())));
                    }
                }
            }
        }
    }
    tbb::parallel_sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    if (opt.progress) opt.progress(0.05);

    const States states(occ, flips.get());
    std::vector<std::uint8_t> keep(keys.size(), 0);
    for_blocks(keys.size(), 0.05, 0.25, opt, [&](std::size_t i) {
        std::uint16_t rows[9][9];
        keep[i] = states.fill(key_origin(keys[i]), rows) ? 1 : 0;
    });
    std::size_t kept = 0;
    for (std::size_t i = 0; i < keys.size(); ++i)
        if (keep[i]) keys[kept++] = keys[i];
    keys.resize(kept);
    keys.shrink_to_fit();
    std::vector<std::uint8_t>().swap(keep);
    std::vector<Block> blocks(keys.size());
    stats.blocks = blocks.size();

    // Corner rows, crossed edges, neighbours.
    std::atomic<std::size_t> cells{0};
    for_blocks(blocks.size(), 0.25, 0.35, opt, [&](std::size_t i) {
        Block& b = blocks[i];
        b.origin = key_origin(keys[i]);
        states.fill(b.origin, b.rows);
        std::size_t mixed = 0;
        for (int x = 0; x < 8; ++x) {
            std::uint64_t cx = 0, cy = 0, cz = 0;
            for (int y = 0; y < 8; ++y) {
                const unsigned r = b.rows[x][y];
                cx |= std::uint64_t((r ^ b.rows[x + 1][y]) & 0xFF) << (8 * y);
                cy |= std::uint64_t((r ^ b.rows[x][y + 1]) & 0xFF) << (8 * y);
                cz |= std::uint64_t((r ^ (r >> 1)) & 0xFF) << (8 * y);
                mixed += std::size_t(popcount64(States::mixed_row(b.rows, x, y)));
            }
            b.cross[0][x] = cx;
            b.cross[1][x] = cy;
            b.cross[2][x] = cz;
        }
        unsigned n = 0;
        for (int a = 0; a < 3; ++a)
            for (int x = 0; x < 8; ++x) {
                b.pre[a][x] = std::uint16_t(n);
                n += unsigned(popcount64(b.cross[a][x]));
            }
        b.nverts = n;
        for (int d = 0; d < 8; ++d) {
            const std::uint64_t k =
                block_key(b.origin.offsetBy(8 * (d & 1), 8 * ((d >> 1) & 1), 8 * ((d >> 2) & 1)));
            const auto it = std::lower_bound(keys.begin(), keys.end(), k);
            b.nb[d] = (it != keys.end() && *it == k) ? std::uint32_t(it - keys.begin()) : kNone;
        }
        cells += mixed;
    });
    stats.surface_cells = cells;
    std::size_t nverts = 0;
    for (Block& b : blocks) {
        b.vbase = std::uint32_t(nverts);
        nverts += b.nverts;
    }
    if (nverts >= kNone / 2) throw Error("the surface has too many vertices for 32-bit indices");

    // 2. Vertices at the crossings.
    Mesh mesh;
    mesh.positions.resize(nverts);
    const float lo_t = float(opt.min_edge_fraction), hi_t = 1.0f - lo_t;
    std::atomic<std::size_t> missing{0};
    // An affine index-to-world map (the usual case) is applied as origin + three axis vectors.
    const bool linear = xform.isLinear();
    const openvdb::Vec3d w0 = xform.indexToWorld(openvdb::Vec3d(0, 0, 0));
    const openvdb::Vec3d wx = xform.indexToWorld(openvdb::Vec3d(1, 0, 0)) - w0;
    const openvdb::Vec3d wy = xform.indexToWorld(openvdb::Vec3d(0, 1, 0)) - w0;
    const openvdb::Vec3d wz = xform.indexToWorld(openvdb::Vec3d(0, 0, 1)) - w0;
    for_blocks(blocks.size(), 0.35, 0.6, opt, [&](std::size_t i) {
        const Block& b = blocks[i];
        const openvdb::Vec3fGrid::TreeType::LeafNodeType* cleaf = nullptr;
        std::size_t miss = 0;
        if (crossings) cleaf = crossings->tree().probeConstLeaf(b.origin);
        std::unique_ptr<FlipGrid::ConstUnsafeAccessor> facc;
        std::unique_ptr<openvdb::Vec3fGrid::ConstUnsafeAccessor> eacc, lacc;
        if (flips) {
            facc = std::make_unique<FlipGrid::ConstUnsafeAccessor>(flips->getConstUnsafeAccessor());
            eacc = std::make_unique<openvdb::Vec3fGrid::ConstUnsafeAccessor>(thin_enter->getConstUnsafeAccessor());
            lacc = std::make_unique<openvdb::Vec3fGrid::ConstUnsafeAccessor>(thin_leave->getConstUnsafeAccessor());
        }
        std::uint32_t v = b.vbase;
        for (int a = 0; a < 3; ++a)
            for (int x = 0; x < 8; ++x)
                for (std::uint64_t bits = b.cross[a][x]; bits; bits &= bits - 1) {
                    const int bit = std::countr_zero(bits);
                    const Coord p = b.origin.offsetBy(x, bit >> 3, bit & 7);
                    float t = 0.5f;
                    bool fp = false, fq = false;
                    openvdb::Vec3f shift(0.0f);
                    if (facc) {
                        Coord q = p;
                        q[a] += 1;
                        fp = facc->isValueOn(p);
                        fq = facc->isValueOn(q);
                    }
                    if (fp || fq) {
                        // One end was made inside for a thin part; the other end is outside.
                        const float s0 = eacc->getValue(p)[a], s1 = lacc->getValue(p)[a];
                        if (s0 >= 0.0f && s1 <= 1.0f && s0 < s1) {
                            t = fp ? s1 : s0;
                        } else {
                            // Nothing known beyond the thin part: hug the point, moved onto the
                            // near face of its part.
                            Coord q = p;
                            q[a] += 1;
                            t = fp ? 0.0f : 1.0f;
                            shift = facc->getValue(fp ? p : q);
                        }
                    } else if (crossings) {
                        const openvdb::Index off = openvdb::Vec3fGrid::TreeType::LeafNodeType::coordToOffset(p);
                        const float c = cleaf && cleaf->isValueOn(off) ? cleaf->getValue(off)[a] : -1.0f;
                        if (c >= 0.0f && c <= 1.0f) t = c;
                        else ++miss;
                    }
                    t = std::clamp(t, lo_t, hi_t);
                    openvdb::Vec3d ip(p.x(), p.y(), p.z());
                    ip[a] += double(t);
                    ip += openvdb::Vec3d(shift);
                    const openvdb::Vec3d w = linear ? w0 + wx * ip.x() + wy * ip.y() + wz * ip.z() : xform.indexToWorld(ip);
                    mesh.positions[v++] = Vec3f(float(w.x()), float(w.y()), float(w.z()));
                }
        if (miss) missing += miss;
    });
    stats.missing_crossings = missing;

    // 3. Triangles: count, then write.
    const bool geometric = opt.ambiguity == MarchingCubesOptions::Ambiguity::Geometric;
    const bool join = opt.ambiguity == MarchingCubesOptions::Ambiguity::Join;
    std::atomic<std::size_t> amb_faces{0}, joined_faces{0};
    auto process = [&](std::size_t bi, bool emit) {
        Block& b = blocks[bi];
        std::uint32_t tri = b.tbase, extra = b.xbase;
        std::uint32_t ntris = 0, nextra = 0;
        std::size_t namb = 0, njoin = 0;
        auto vertex = [&](int x, int y, int z, int e) -> std::uint32_t {
            const mc::EdgeDef d = mc::kEdges[std::size_t(e)];
            int px = x + (d.corner & 1), py = y + ((d.corner >> 1) & 1), pz = z + ((d.corner >> 2) & 1);
            const std::uint32_t nbi = b.nb[(px >> 3) | ((py >> 3) << 1) | ((pz >> 3) << 2)];
            if (nbi == kNone) throw Error("marching cubes: a crossed edge has no owning block (internal error)");
            const Block& o = blocks[nbi];
            px &= 7; py &= 7; pz &= 7;
            const int bit = 8 * py + pz;
            return o.vbase + o.pre[d.axis][px] +
                   std::uint32_t(popcount64(o.cross[d.axis][px] & ((std::uint64_t(1) << bit) - 1)));
        };
        auto dist = [&](std::uint32_t i, std::uint32_t j) {
            const Vec3d a(mesh.positions[i]), c(mesh.positions[j]);
            return length(a - c);
        };
        for (int x = 0; x < 8; ++x)
            for (int y = 0; y < 8; ++y)
                for (unsigned zs = States::mixed_row(b.rows, x, y); zs; zs &= zs - 1) {
                    const int z = std::countr_zero(zs);
                    unsigned config = 0;
                    for (int c = 0; c < 8; ++c)
                        config |= unsigned((b.rows[x + (c & 1)][y + ((c >> 1) & 1)] >> (z + ((c >> 2) & 1))) & 1u) << c;
                    const unsigned amb = table.ambiguous_faces(config);
                    unsigned bits = table.separating_bits(config);
                    if (amb) {
                        if (join) bits = ~bits & amb;
                        else if (geometric) {
                            for (int f = 0; f < 6; ++f) {
                                if (!((amb >> f) & 1)) continue;
                                const auto& fe = mc::kFaceEdges[std::size_t(f)];
                                std::uint32_t id[4];
                                for (int k = 0; k < 4; ++k) id[k] = vertex(x, y, z, fe[std::size_t(k)]);
                                const double la = dist(id[0], id[2]) + dist(id[1], id[3]);
                                const double lb = dist(id[0], id[3]) + dist(id[1], id[2]);
                                if (la != lb) bits = (bits & ~(1u << f)) | (lb < la ? (1u << f) : 0u);
                            }
                        }
                        namb += std::size_t(popcount64(amb));
                        njoin += std::size_t(popcount64((bits ^ table.separating_bits(config)) & amb));
                    }
                    const mc::Case& cs = table.lookup(config, bits);
                    for (std::uint32_t li = 0; li < cs.loop_count; ++li) {
                        const mc::Loop& loop = table.loop(cs.first_loop + li);
                        const int n = loop.size;
                        if (loop.mode == mc::Loop::Centroid) {
                            ntris += std::uint32_t(n);
                            ++nextra;
                        } else {
                            ntris += std::uint32_t(n - 2);
                        }
                        if (!emit) continue;
                        std::uint32_t id[12];
                        for (int k = 0; k < n; ++k) id[k] = vertex(x, y, z, loop.edges[std::size_t(k)]);
                        auto put = [&](std::uint32_t i0, std::uint32_t i1, std::uint32_t i2) {
                            mesh.triangles[tri++] = {i0, i1, i2};
                        };
                        if (loop.mode == mc::Loop::Centroid) {
                            Vec3d c{};
                            for (int k = 0; k < n; ++k) c += Vec3d(mesh.positions[id[k]]);
                            mesh.positions[extra] = Vec3f(c / double(n));
                            for (int k = 0; k < n; ++k) put(id[k], id[(k + 1) % n], extra);
                            ++extra;
                        } else if (loop.mode == mc::Loop::Fixed) {
                            for (int k = 0; k < loop.tri_count; ++k)
                                put(id[loop.tris[std::size_t(k)][0]], id[loop.tris[std::size_t(k)][1]],
                                    id[loop.tris[std::size_t(k)][2]]);
                        } else {
                            int apex = std::countr_zero(unsigned(loop.fan_apexes));
                            if (n == 4 && (loop.fan_apexes & 5u) && (loop.fan_apexes & 10u)) {
                                // A quad: the shorter diagonal.
                                const Vec3f d02 = mesh.positions[id[0]] - mesh.positions[id[2]];
                                const Vec3f d13 = mesh.positions[id[1]] - mesh.positions[id[3]];
                                apex = dot(d02, d02) <= dot(d13, d13) ? 0 : 1;
                            } else if (n > 3 && popcount64(unsigned(loop.fan_apexes)) > 1) {
                                // Best fan: the one whose worst triangle is least flipped or thin
                                // against the loop's mean plane.
                                Vec3d P[12];
                                for (int k = 0; k < n; ++k) P[k] = Vec3d(mesh.positions[id[k]]);
                                Vec3d N{};
                                for (int k = 0; k < n; ++k) N += cross(P[k], P[(k + 1) % n]);
                                double best = -std::numeric_limits<double>::infinity();
                                for (int k = 0; k < n; ++k) {
                                    if (!((loop.fan_apexes >> k) & 1)) continue;
                                    double worst = std::numeric_limits<double>::infinity();
                                    for (int i = 1; i + 1 < n; ++i) {
                                        const Vec3d& A = P[k];
                                        const Vec3d& B = P[(k + i) % n];
                                        const Vec3d& C = P[(k + i + 1) % n];
                                        const double q = dot(cross(B - A, C - A), N) /
                                                         (dot(B - A, B - A) + dot(C - B, C - B) + dot(A - C, A - C));
                                        worst = std::min(worst, q);
                                    }
                                    if (worst > best) { best = worst; apex = k; }
                                }
                            }
                            for (int i = 1; i + 1 < n; ++i) put(id[apex], id[(apex + i) % n], id[(apex + i + 1) % n]);
                        }
                    }
                }
        if (!emit) {
            b.ntris = ntris;
            b.nextra = nextra;
            if (namb) amb_faces += namb;
            if (njoin) joined_faces += njoin;
        }
    };
    for_blocks(blocks.size(), 0.6, 0.75, opt, [&](std::size_t i) { process(i, false); });
    std::size_t ntris = 0, nextra = 0;
    for (Block& b : blocks) {
        b.tbase = std::uint32_t(ntris);
        b.xbase = std::uint32_t(nverts + nextra);
        ntris += b.ntris;
        nextra += b.nextra;
    }
    if (nverts + nextra >= kNone / 2 || ntris >= kNone / 2)
        throw Error("the surface has too many triangles for 32-bit indices");
    mesh.positions.resize(nverts + nextra);
    mesh.triangles.resize(ntris);
    for_blocks(blocks.size(), 0.75, 1.0, opt, [&](std::size_t i) { process(i, true); });
    stats.ambiguous_faces = amb_faces;
    stats.joined_faces = joined_faces;
    stats.centroid_vertices = nextra;
    if (stats_out) *stats_out = stats;
    return mesh;
}

} // namespace cm
