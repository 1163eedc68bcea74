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
// Phase 1 and the block layout are in mc_blocks.cpp.
#include "marching_cubes.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <limits>
#include <map>
#include <memory>

#include <tbb/enumerable_thread_specific.h>

#include "core/error.h"
#include "mc_blocks.h"
#include "mc_table.h"
#include "mc_thin.h"
#include "util/prefault.h"

namespace cm {
namespace {

using mc::Block;
using mc::FlipGrid;
using mc::for_blocks;
using mc::kNone;
using mc::mixed_row;
using mc::popcount64;
using mc::promote_thin;
using mc::ShiftedVertex;
using openvdb::Coord;

/// True when both transforms put the grid points at the same places.
bool same_lattice(const openvdb::math::Transform& a, const openvdb::math::Transform& b) {
    const double tol = 1e-9 * std::max(1.0, a.voxelSize()[0]);
    for (const openvdb::Vec3d p :
         {openvdb::Vec3d(0, 0, 0), openvdb::Vec3d(1, 0, 0), openvdb::Vec3d(0, 1, 0), openvdb::Vec3d(0, 0, 1)})
        if ((a.indexToWorld(p) - b.indexToWorld(p)).length() > tol) return false;
    return true;
}

/// The grids beside the occupancy that place the vertices, each on the occupancy's lattice,
/// and the points made inside for thin parts (`flips`, null when there are none).
struct Sources {
    const openvdb::Vec3fGrid* crossings = nullptr;
    const openvdb::Vec3fGrid *thin_enter = nullptr, *thin_leave = nullptr;
    FlipGrid::Ptr flips;
};

Sources find_sources(const Volume& vol, const MarchingCubesOptions& opt, MarchingCubesStats& stats) {
    const auto& xform = vol.occupancy->transform();
    Sources src;
    src.crossings = (opt.use_crossings && vol.crossings) ? vol.crossings.get() : nullptr;
    if (src.crossings && !same_lattice(src.crossings->transform(), xform))
        throw Error("the crossings grid is not on the occupancy's transform");
    if (opt.use_thin) {
        src.thin_enter = dynamic_cast<const openvdb::Vec3fGrid*>(vol.find_extra("thin_enter").get());
        src.thin_leave = dynamic_cast<const openvdb::Vec3fGrid*>(vol.find_extra("thin_leave").get());
        if (!src.thin_enter || !src.thin_leave) src.thin_enter = src.thin_leave = nullptr;
        if (src.thin_enter &&
            (!same_lattice(src.thin_enter->transform(), xform) || !same_lattice(src.thin_leave->transform(), xform)))
            throw Error("the thin-part grids are not on the occupancy's transform");
    }
    if (src.thin_enter) {
        src.flips = promote_thin(vol, *src.thin_enter, *src.thin_leave, stats.thin_points);
        if (src.flips->tree().empty()) src.flips.reset();
    }
    return src;
}

/// Numbers the vertices block by block (each block's vbase); returns how many there are.
std::size_t number_vertices(std::vector<Block>& blocks) {
    std::size_t nverts = 0;
    for (Block& b : blocks) {
        b.vbase = std::uint32_t(nverts);
        nverts += b.nverts;
    }
    if (nverts >= kNone / 2) throw Error("the surface has too many vertices for 32-bit indices");
    return nverts;
}

/// 2. The vertex of every crossed edge of a block: at the edge's crossing when the volume
/// has one, else at its midpoint; edges to a point made inside follow the thin part.
class VertexPlacer {
public:
    VertexPlacer(const Sources& src, const openvdb::math::Transform& xform, const MarchingCubesOptions& opt)
        : src_(src),
          xform_(xform),
          lo_t_(float(opt.min_edge_fraction)),
          hi_t_(1.0f - lo_t_),
          linear_(xform.isLinear()),
          w0_(xform.indexToWorld(openvdb::Vec3d(0, 0, 0))),
          wx_(xform.indexToWorld(openvdb::Vec3d(1, 0, 0)) - w0_),
          wy_(xform.indexToWorld(openvdb::Vec3d(0, 1, 0)) - w0_),
          wz_(xform.indexToWorld(openvdb::Vec3d(0, 0, 1)) - w0_) {}

    /// Writes the vertices of `b` into positions[b.vbase...]; returns how many of its edges
    /// had no valid crossing.
    /// Vertices moved onto the near face of a thin part are added to `shifted`.
    std::size_t place(const Block& b, std::vector<Vec3f>& positions, std::vector<ShiftedVertex>& shifted,
                      std::vector<std::array<std::int32_t, 4>>* edges = nullptr) const {
        const openvdb::Vec3fGrid::TreeType::LeafNodeType* cleaf = nullptr;
        std::size_t miss = 0;
        if (src_.crossings) cleaf = src_.crossings->tree().probeConstLeaf(b.origin);
        std::unique_ptr<FlipGrid::ConstUnsafeAccessor> facc;
        std::unique_ptr<openvdb::Vec3fGrid::ConstUnsafeAccessor> eacc, lacc;
        if (src_.flips) {
            facc = std::make_unique<FlipGrid::ConstUnsafeAccessor>(src_.flips->getConstUnsafeAccessor());
            eacc = std::make_unique<openvdb::Vec3fGrid::ConstUnsafeAccessor>(src_.thin_enter->getConstUnsafeAccessor());
            lacc = std::make_unique<openvdb::Vec3fGrid::ConstUnsafeAccessor>(src_.thin_leave->getConstUnsafeAccessor());
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
                    } else if (src_.crossings) {
                        const openvdb::Index off = openvdb::Vec3fGrid::TreeType::LeafNodeType::coordToOffset(p);
                        const float c = cleaf && cleaf->isValueOn(off) ? cleaf->getValue(off)[a] : -1.0f;
                        if (c >= 0.0f && c <= 1.0f) t = c;
                        else ++miss;
                    }
                    t = std::clamp(t, lo_t_, hi_t_);
                    if (edges) (*edges)[v] = {p.x(), p.y(), p.z(), a};
                    if (shift != openvdb::Vec3f(0.0f)) shifted.push_back({v, world(p, a, t, openvdb::Vec3f(0.0f))});
                    positions[v++] = world(p, a, t, shift);
                }
        return miss;
    }

private:
    /// The point at `t` along the edge from p along axis a, moved by `shift` (index space).
    Vec3f world(const Coord& p, int a, float t, const openvdb::Vec3f& shift) const {
        openvdb::Vec3d ip(p.x(), p.y(), p.z());
        ip[a] += double(t);
        ip += openvdb::Vec3d(shift);
        const openvdb::Vec3d w = linear_ ? w0_ + wx_ * ip.x() + wy_ * ip.y() + wz_ * ip.z() : xform_.indexToWorld(ip);
        return Vec3f(float(w.x()), float(w.y()), float(w.z()));
    }

    const Sources& src_;
    const openvdb::math::Transform& xform_;
    const float lo_t_, hi_t_;
    // An affine index-to-world map (the usual case) is applied as origin + three axis vectors.
    const bool linear_;
    const openvdb::Vec3d w0_, wx_, wy_, wz_;
};

/// 3. The triangles of a block's cells: counted first (emit false: the block's ntris and
/// nextra), then written at the block's offsets (emit true).
class Triangulator {
public:
    Triangulator(std::vector<Block>& blocks, Mesh& mesh, const MarchingCubesOptions& opt, MarchingCubesPatches* patches)
        : blocks_(blocks),
          mesh_(mesh),
          patches_(patches),
          table_(mc::Table::get()),
          geometric_(opt.ambiguity == MarchingCubesOptions::Ambiguity::Geometric),
          join_(opt.ambiguity == MarchingCubesOptions::Ambiguity::Join) {}

    std::size_t ambiguous_faces() const { return amb_faces_; }
    std::size_t joined_faces() const { return joined_faces_; }

    void process(std::size_t bi, bool emit) {
        Block& b = blocks_[bi];
        std::uint32_t tri = b.tbase, extra = b.xbase, lp = b.lbase;
        std::uint32_t ntris = 0, nextra = 0, nloops = 0;
        std::size_t namb = 0, njoin = 0;
        for (int x = 0; x < 8; ++x)
            for (int y = 0; y < 8; ++y)
                for (unsigned zs = mixed_row(b.rows, x, y); zs; zs &= zs - 1) {
                    const int z = std::countr_zero(zs);
                    unsigned config = 0;
                    for (int c = 0; c < 8; ++c)
                        config |= unsigned((b.rows[x + (c & 1)][y + ((c >> 1) & 1)] >> (z + ((c >> 2) & 1))) & 1u) << c;
                    const unsigned amb = table_.ambiguous_faces(config);
                    unsigned bits = table_.separating_bits(config);
                    if (amb) {
                        bits = resolve(b, x, y, z, config, amb);
                        namb += std::size_t(popcount64(amb));
                        njoin += std::size_t(popcount64((bits ^ table_.separating_bits(config)) & amb));
                    }
                    const mc::Case& cs = table_.lookup(config, bits);
                    nloops += cs.loop_count;
                    for (std::uint32_t li = 0; li < cs.loop_count; ++li) {
                        const mc::Loop& loop = table_.loop(cs.first_loop + li);
                        const int n = loop.size;
                        if (loop.mode == mc::Loop::Centroid) {
                            ntris += std::uint32_t(n);
                            ++nextra;
                        } else {
                            ntris += std::uint32_t(n - 2);
                        }
                        if (!emit) continue;
                        std::uint32_t id[12];
                        for (int k = 0; k < n; ++k) id[k] = vertex(b, x, y, z, loop.edges[std::size_t(k)]);
                        const std::uint32_t tri0 = tri;
                        write_loop(loop, id, tri, extra);
                        if (patches_) {
                            for (std::uint32_t t = tri0; t < tri; ++t) patches_->triangle_loop[t] = lp;
                            patches_->loop_cell[lp] = b.origin.offsetBy(x, y, z);
                            if (loop.mode == mc::Loop::Centroid) patches_->vertex_edge[extra - 1] = {0, 0, 0, -1};
                        }
                        ++lp;
                    }
                }
        if (!emit) {
            b.ntris = ntris;
            b.nextra = nextra;
            b.nloops = nloops;
            if (namb) amb_faces_ += namb;
            if (njoin) joined_faces_ += njoin;
        }
    }

private:
    /// The vertex on edge e of cell (x, y, z) of `b`, found in the block that owns the edge.
    std::uint32_t vertex(const Block& b, int x, int y, int z, int e) const {
        const mc::EdgeDef d = mc::kEdges[std::size_t(e)];
        int px = x + (d.corner & 1), py = y + ((d.corner >> 1) & 1), pz = z + ((d.corner >> 2) & 1);
        const std::uint32_t nbi = b.nb[(px >> 3) | ((py >> 3) << 1) | ((pz >> 3) << 2)];
        if (nbi == kNone) throw Error("marching cubes: a crossed edge has no owning block (internal error)");
        const Block& o = blocks_[nbi];
        px &= 7;
        py &= 7;
        pz &= 7;
        const int bit = 8 * py + pz;
        return o.vbase + o.pre[d.axis][px] +
               std::uint32_t(popcount64(o.cross[d.axis][px] & ((std::uint64_t(1) << bit) - 1)));
    }

    double dist(std::uint32_t i, std::uint32_t j) const {
        const Vec3d a(mesh_.positions[i]), c(mesh_.positions[j]);
        return length(a - c);
    }

    /// Face bits (pairing B) for the ambiguous faces `amb` of cell (x, y, z) in `config`.
    unsigned resolve(const Block& b, int x, int y, int z, unsigned config, unsigned amb) const {
        unsigned bits = table_.separating_bits(config);
        if (join_) bits = ~bits & amb;
        else if (geometric_) {
            for (int f = 0; f < 6; ++f) {
                if (!((amb >> f) & 1)) continue;
                const auto& fe = mc::kFaceEdges[std::size_t(f)];
                std::uint32_t id[4];
                for (int k = 0; k < 4; ++k) id[k] = vertex(b, x, y, z, fe[std::size_t(k)]);
                const double la = dist(id[0], id[2]) + dist(id[1], id[3]);
                const double lb = dist(id[0], id[3]) + dist(id[1], id[2]);
                if (la != lb) bits = (bits & ~(1u << f)) | (lb < la ? (1u << f) : 0u);
            }
        }
        return bits;
    }

    /// Writes the triangles of `loop` (its vertices: id) from triangle `tri` on, and its
    /// centroid vertex, if it has one, at `extra`.
    void write_loop(const mc::Loop& loop, const std::uint32_t* id, std::uint32_t& tri, std::uint32_t& extra) {
        const int n = loop.size;
        auto put = [&](std::uint32_t i0, std::uint32_t i1, std::uint32_t i2) { mesh_.triangles[tri++] = {i0, i1, i2}; };
        if (loop.mode == mc::Loop::Centroid) {
            Vec3d c{};
            for (int k = 0; k < n; ++k) c += Vec3d(mesh_.positions[id[k]]);
            mesh_.positions[extra] = Vec3f(c / double(n));
            for (int k = 0; k < n; ++k) put(id[k], id[(k + 1) % n], extra);
            ++extra;
        } else if (loop.mode == mc::Loop::Fixed) {
            for (int k = 0; k < loop.tri_count; ++k)
                put(id[loop.tris[std::size_t(k)][0]], id[loop.tris[std::size_t(k)][1]],
                    id[loop.tris[std::size_t(k)][2]]);
        } else {
            const int apex = fan_apex(loop, id);
            for (int i = 1; i + 1 < n; ++i) put(id[apex], id[(apex + i) % n], id[(apex + i + 1) % n]);
        }
    }

    /// The apex of a Fan loop's fan.
    int fan_apex(const mc::Loop& loop, const std::uint32_t* id) const {
        const int n = loop.size;
        int apex = std::countr_zero(unsigned(loop.fan_apexes));
        if (n == 4 && (loop.fan_apexes & 5u) && (loop.fan_apexes & 10u)) {
            // A quad: the shorter diagonal.
            const Vec3f d02 = mesh_.positions[id[0]] - mesh_.positions[id[2]];
            const Vec3f d13 = mesh_.positions[id[1]] - mesh_.positions[id[3]];
            apex = dot(d02, d02) <= dot(d13, d13) ? 0 : 1;
        } else if (n > 3 && popcount64(unsigned(loop.fan_apexes)) > 1) {
            // Best fan: the one whose worst triangle is least flipped or thin
            // against the loop's mean plane.
            Vec3d P[12];
            for (int k = 0; k < n; ++k) P[k] = Vec3d(mesh_.positions[id[k]]);
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
                    const double q =
                        dot(cross(B - A, C - A), N) / (dot(B - A, B - A) + dot(C - B, C - B) + dot(A - C, A - C));
                    worst = std::min(worst, q);
                }
                if (worst > best) {
                    best = worst;
                    apex = k;
                }
            }
        }
        return apex;
    }

    std::vector<Block>& blocks_;
    Mesh& mesh_;
    MarchingCubesPatches* patches_;
    const mc::Table& table_;
    const bool geometric_, join_;
    std::atomic<std::size_t> amb_faces_{0}, joined_faces_{0};
};

// The extraction (see the top of the file) into `mesh` and `stats`; `patches` (may be null)
// gets the loops behind the triangles.
void extract(const Volume& vol, const MarchingCubesOptions& opt, const Progress& progress, Mesh& mesh,
             MarchingCubesStats& stats, MarchingCubesPatches* patches) {
    if (!vol.occupancy) throw Error("the volume has no occupancy grid");
    const openvdb::BoolGrid& occ = *vol.occupancy;
    const Sources src = find_sources(vol, opt, stats);
    stats.refined = src.crossings != nullptr;

    // 1. The blocks with surface: corner rows, crossed edges, neighbours.
    std::vector<Block> blocks = mc::find_blocks(occ, src.flips.get(), progress, stats);
    const std::size_t nverts = number_vertices(blocks);

    // 2. Vertices at the crossings.
    reserve_prefaulted(mesh.positions, nverts);
    mesh.positions.resize(nverts);
    if (patches) patches->vertex_edge.resize(nverts);
    const VertexPlacer placer(src, occ.transform(), opt);
    std::atomic<std::size_t> missing{0};
    tbb::enumerable_thread_specific<std::vector<ShiftedVertex>> shifted;
    for_blocks(blocks.size(), 0.35, 0.6, progress, [&](std::size_t i) {
        if (const std::size_t miss =
                placer.place(blocks[i], mesh.positions, shifted.local(), patches ? &patches->vertex_edge : nullptr))
            missing += miss;
    });
    stats.missing_crossings = missing;

    // 3. Triangles: count, then write.
    Triangulator triangulator(blocks, mesh, opt, patches);
    for_blocks(blocks.size(), 0.6, 0.75, progress, [&](std::size_t i) { triangulator.process(i, false); });
    std::size_t ntris = 0, nextra = 0, nloops = 0;
    for (Block& b : blocks) {
        b.tbase = std::uint32_t(ntris);
        b.xbase = std::uint32_t(nverts + nextra);
        b.lbase = std::uint32_t(nloops);
        ntris += b.ntris;
        nextra += b.nextra;
        nloops += b.nloops;
    }
    if (nverts + nextra >= kNone / 2 || ntris >= kNone / 2)
        throw Error("the surface has too many triangles for 32-bit indices");
    mesh.positions.resize(nverts + nextra);
    reserve_prefaulted(mesh.triangles, ntris);
    mesh.triangles.resize(ntris);
    if (patches) {
        patches->vertex_edge.resize(nverts + nextra);
        patches->triangle_loop.resize(ntris);
        patches->loop_cell.resize(nloops);
    }
    for_blocks(blocks.size(), 0.75, 1.0, progress, [&](std::size_t i) { triangulator.process(i, true); });
    stats.ambiguous_faces = triangulator.ambiguous_faces();
    stats.joined_faces = triangulator.joined_faces();
    stats.centroid_vertices = nextra;
    // 4. Shifted thin-part vertices whose faces cross another face go back onto their edges.
    std::vector<ShiftedVertex> all_shifted;
    for (auto& l : shifted) all_shifted.insert(all_shifted.end(), l.begin(), l.end());
    stats.thin_shifted = all_shifted.size();
    stats.thin_put_back = mc::untangle_thin(mesh, all_shifted, nverts, occ.transform());
}

} // namespace

Result<Mesh, MarchingCubesStats> marching_cubes(const Volume& vol, const MarchingCubesOptions& opt, Progress progress) {
    Result<Mesh, MarchingCubesStats> r;
    extract(vol, opt, progress, r.value, r.stats, nullptr);
    return r;
}

MarchingCubesLoops marching_cubes_loops(const Volume& vol, const MarchingCubesOptions& opt, Progress progress) {
    MarchingCubesLoops r;
    extract(vol, opt, progress, r.mesh, r.stats, &r.patches);
    return r;
}

void MarchingCubesOptions::declare(ParamBinder& b) {
    declare_ambiguity(b, "ambiguous faces");
    b.add(use_crossings, ParamSpec::Bool("crossings", true,
                                         "place vertices at the volume's exact crossings (false: edge midpoints, "
                                         "plain binary Marching Cubes)"));
    declare_thin_parts(b);
    b.add(min_edge_fraction, ParamSpec::Float("min_edge_fraction", 0.01, 0.0001, 0.25, "cell",
                                              "crossings nearer than this to a grid point are moved out to it, so "
                                              "no two vertices coincide"));
}

void MarchingCubesOptions::declare_ambiguity(ParamBinder& b, const std::string& what) {
    b.add(ambiguity,
          ParamSpec::Enum("ambiguity", "geometric", {"geometric", "separate", "join"},
                          what + ": geometric pairs the crossings by the shorter cut; separate keeps diagonal "
                                 "inside corners apart; join connects them"),
          {Ambiguity::Geometric, Ambiguity::Separate, Ambiguity::Join});
}

void MarchingCubesOptions::declare_thin_parts(ParamBinder& b) {
    b.add(use_thin, ParamSpec::Bool("thin_parts", true,
                                    "keep parts thinner than a cell that the refinement found between grid points"));
}

void MarchingCubesStats::report(Metrics& m) const {
    m.count("surface_cells", surface_cells);
    m.count("blocks", blocks);
    m.count("ambiguous_faces", ambiguous_faces / 2); // each face is seen from both its cells
    m.count("joined_faces", joined_faces / 2);
    m.count("centroid_vertices", centroid_vertices);
    m.count("thin_points", thin_points);
    m.count("thin_put_back", thin_put_back);
    m.flag("refined", refined);
    m.warned_count("missing_crossings", missing_crossings,
                   "crossed edge(s) have no crossing in the refined volume; their vertices sit at the edge midpoint");
}

} // namespace cm
