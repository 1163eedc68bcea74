// Dual Marching Cubes (Schaefer & Warren 2004) in its manifold form (Schaefer, Ju & Warren
// 2007), on the Marching Cubes loops:
//
// 1. Marching Cubes gives the topology: its loops are the discs of surface in each cell
//    (several in a cell where the surface passes more than once), with the ambiguous faces
//    resolved consistently on both sides, and its vertices are the crossings.
// 2. Every crossing gets its exact normal (hull_normal.h, or refine's stored grids).
// 3. Every loop gets one vertex: the minimum of the QEF sum_i (n_i . (x - p_i))^2 over its
//    crossings p_i, solved with a truncated pseudo-inverse about their mean and clamped into
//    the cell, so the vertex sits on the corner or crease the normals describe.
// 4. Every crossing (a crossed lattice edge) gets one polygon: the loops around it in the
//    order of its Marching Cubes triangle fan (four, one per cell around the edge), so the
//    dual mesh is closed and oriented as the Marching Cubes mesh is; quads are split along
//    the diagonal that bends them least.
//
// The dual of the loops is 2-manifold when no two loops share more than one edge. Two
// loops in neighbouring cells share two when their common face is ambiguous and each loop
// holds both of its segments (the face's inside corners joined on both sides, as where a
// part one cell thin crosses a face diagonally): their two vertices would be joined by two
// edges, one edge of four polygons. One of the two loops is then cut in two by a chord
// across the cell, each piece holding one segment, and gets a vertex per piece
// (split_shared_faces).
#include "dual_mc.h"

#include "geometry/mesh_intersect.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "dmc_octree.h"
#include "geometry/carved_hull.h"
#include "geometry/hull_normal.h"

namespace cm {
namespace {

/// The Hermite normals of the crossings (one per Marching Cubes vertex, zero for centre vertices).
std::vector<Vec3f> crossing_normals(const Volume& vol, const Mesh& mc, const MarchingCubesPatches& P,
                                    DualMcOptions::Normals mode, double normal_px, const char*& source) {
    std::vector<Vec3f> N(mc.positions.size(), Vec3f(0, 0, 0));
    const openvdb::Vec3fGrid* stored[3] = {nullptr, nullptr, nullptr};
    const char* names[3] = {"normal_x", "normal_y", "normal_z"};
    for (int a = 0; a < 3; ++a) stored[a] = dynamic_cast<const openvdb::Vec3fGrid*>(vol.find_extra(names[a]).get());
    const bool have_stored = stored[0] && stored[1] && stored[2];
    std::unique_ptr<VisualHull> hull;
    if (mode == DualMcOptions::Normals::Views || (mode == DualMcOptions::Normals::Auto && !have_stored)) {
        if (vol.views && !vol.views->views.empty()) hull = carved_hull(*vol.occupancy, *vol.views);
        else if (mode == DualMcOptions::Normals::Views)
            throw Error("normals: views asks for the views' outlines, but the volume has no views");
    }
    // The Marching Cubes vertex normals: the fallback where no exact normal is known.
    Mesh approx;
    approx.positions = mc.positions;
    approx.triangles = mc.triangles;
    approx.compute_normals();
    const bool use_mesh = mode == DualMcOptions::Normals::Mesh || (!hull && !have_stored);
    source = use_mesh ? "mesh" : (hull ? "views" : "stored");
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, N.size(), 4096), [&](const tbb::blocked_range<std::size_t>& r) {
            std::unique_ptr<openvdb::Vec3fGrid::ConstAccessor> acc[3];
            if (!use_mesh && !hull)
                for (int a = 0; a < 3; ++a)
                    acc[a] = std::make_unique<openvdb::Vec3fGrid::ConstAccessor>(stored[a]->getConstAccessor());
            for (std::size_t v = r.begin(); v != r.end(); ++v) {
                const auto& e = P.vertex_edge[v];
                if (e[3] < 0) continue;
                if (use_mesh) {
                    N[v] = approx.normals[v];
                } else if (hull) {
                    const Vec3d n = hull_normal(*hull, Vec3d(mc.positions[v]), normal_px).normal;
                    N[v] = dot(n, n) > 0 ? Vec3f(n) : approx.normals[v];
                } else {
                    const openvdb::Coord c(e[0], e[1], e[2]);
                    openvdb::Vec3f n;
                    if (acc[e[3]]->probeValue(c, n) && n.lengthSqr() > 0.5f) N[v] = Vec3f(n.x(), n.y(), n.z());
                    else N[v] = approx.normals[v]; // a vertex moved onto a thin part: no stored normal
                }
            }
        });
    return N;
}

/// The triangles of the Marching Cubes mesh around each vertex (CSR), rotated so the
/// vertex comes first.
struct Fans {
    std::vector<Index> first;              ///< per vertex, into `tri`
    std::vector<std::array<Index, 3>> tri; ///< (triangle, next vertex, previous vertex)
};

Fans build_fans(const Mesh& m) {
    Fans f;
    f.first.assign(m.positions.size() + 1, 0);
    for (const auto& t : m.triangles)
        for (Index v : t) ++f.first[v + 1];
    for (std::size_t v = 0; v < m.positions.size(); ++v) f.first[v + 1] += f.first[v];
    f.tri.resize(f.first.back());
    std::vector<Index> fill(f.first.begin(), f.first.end() - 1);
    for (Index t = 0; t < Index(m.triangles.size()); ++t) {
        const auto& tr = m.triangles[t];
        for (int k = 0; k < 3; ++k) f.tri[fill[tr[k]]++] = {t, tr[(k + 1) % 3], tr[(k + 2) % 3]};
    }
    return f;
}

/// The loops around vertex v, in the order of its fan (outward orientation); returns the count.
int ring(const Fans& f, const MarchingCubesPatches& P, Index v, Index* out, int cap) {
    const Index b = f.first[v], e = f.first[v + 1];
    const int deg = int(e - b);
    if (deg == 0) return 0;
    Index order[32];
    if (deg > 32) return -1;
    // Walk the fan: the triangle (v, a, c) is followed by the one that starts (v, c, ...).
    order[0] = b;
    for (int k = 1; k < deg; ++k) {
        const Index c = f.tri[order[k - 1]][2];
        Index next = e;
        for (Index j = b; j < e; ++j)
            if (f.tri[j][1] == c) next = j;
        if (next == e) return -1;
        order[k] = next;
    }
    int n = 0;
    for (int k = 0; k < deg; ++k) {
        const Index loop = P.triangle_loop[f.tri[order[k]][0]];
        if (n > 0 && out[n - 1] == loop) continue;
        if (n == cap) return -1;
        out[n++] = loop;
    }
    while (n > 1 && out[n - 1] == out[0]) --n;
    return n;
}

/// The faces (bit 2 n + side) of `cell` that hold the lattice edge e (start point, axis).
unsigned face_mask(const std::array<std::int32_t, 4>& e, const openvdb::Coord& cell) {
    unsigned m = 0;
    for (int n = 0; n < 3; ++n) {
        if (n == e[3]) continue;
        const int d = e[std::size_t(n)] - cell[n];
        if (d == 0 || d == 1) m |= 1u << (2 * n + d);
    }
    return m;
}

/// A loop cut into pieces by chords: each piece a cycle of crossings in outward order.
struct SplitLoop {
    std::vector<Index> cycle;               ///< the whole loop
    std::vector<std::vector<Index>> pieces; ///< pieces[0] keeps the loop's index
    std::vector<Index> id;                  ///< each piece's loop index
};

/// The loop's crossings in outward order: the boundary of its triangles [t0, t1).
std::vector<Index> loop_cycle(const Mesh& mc, Index t0, Index t1) {
    std::vector<std::pair<Index, Index>> e, b;
    for (Index t = t0; t < t1; ++t)
        for (int k = 0; k < 3; ++k) e.emplace_back(mc.triangles[t][k], mc.triangles[t][(k + 1) % 3]);
    for (const auto& d : e)
        if (std::find(e.begin(), e.end(), std::pair(d.second, d.first)) == e.end()) b.push_back(d);
    std::vector<Index> cyc;
    if (b.empty()) return cyc;
    cyc.push_back(b[0].first);
    while (cyc.size() < b.size()) {
        const auto it = std::find_if(b.begin(), b.end(), [&](const auto& d) { return d.first == cyc.back(); });
        if (it == b.end() || it->second == cyc.front()) break;
        cyc.push_back(it->second);
    }
    return cyc;
}

/// The loop of `cell` around crossing x (every crossing is in one loop of each of its cells).
Index loop_around(const Fans& f, const MarchingCubesPatches& P, const std::vector<openvdb::Coord>& cell_of, Index x,
                  const openvdb::Coord& cell) {
    for (Index j = f.first[x]; j < f.first[x + 1]; ++j) {
        const Index l = P.triangle_loop[f.tri[j][0]];
        if (cell_of[l] == cell) return l;
    }
    return kNoIndex;
}

/// Cuts loops so that no two loops share two edges (see the top of the file): where loops
/// A < B in neighbouring cells each hold all four crossings of their common face, A's piece
/// that holds both of the face's segments is cut by a chord between the middles of the two
/// arcs that separate them. New pieces get loop indices from nloops on (D.loop_cell grows);
/// D.loop_first / loop_cross are rebuilt with the pieces' crossings. Returns the cut loops;
/// split_of[l] indexes them (-1: not cut).
std::vector<SplitLoop> split_shared_faces(const Mesh& mc, const MarchingCubesPatches& P, const Fans& fans,
                                          const std::vector<Index>& tfirst, DualMesh& D, std::vector<int>& split_of) {
    const std::size_t nloops = D.loop_cell.size();
    auto face_count = [&](Index l, int f) {
        int n = 0;
        for (Index i = D.loop_first[l]; i < D.loop_first[l + 1]; ++i)
            n += (face_mask(P.vertex_edge[D.loop_cross[i]], D.loop_cell[l]) >> f) & 1;
        return n;
    };
    std::vector<std::pair<Index, int>> todo; // (loop, face) to cut
    for (Index a = 0; a < Index(nloops); ++a) {
        const Index n = D.loop_first[a + 1] - D.loop_first[a];
        if (n < 6) continue; // both segments of a face and a way round between them
        for (int f = 0; f < 6; ++f) {
            if (face_count(a, f) != 4) continue;
            openvdb::Coord nb = D.loop_cell[a];
            nb[f / 2] += (f & 1) ? 1 : -1;
            Index x = kNoIndex;
            for (Index i = D.loop_first[a]; i < D.loop_first[a + 1] && x == kNoIndex; ++i)
                if ((face_mask(P.vertex_edge[D.loop_cross[i]], D.loop_cell[a]) >> f) & 1) x = D.loop_cross[i];
            const Index b = loop_around(fans, P, D.loop_cell, x, nb);
            if (b != kNoIndex && a < b && face_count(b, f ^ 1) == 4) todo.emplace_back(a, f);
        }
    }
    std::vector<SplitLoop> splits;
    if (todo.empty()) return splits;
    split_of.assign(nloops, -1);
    Index next_id = Index(nloops);
    for (const auto& [a, f] : todo) {
        if (split_of[a] < 0) {
            split_of[a] = int(splits.size());
            SplitLoop s;
            s.cycle = loop_cycle(mc, tfirst[a], tfirst[a + 1]);
            s.pieces = {s.cycle};
            s.id = {a};
            splits.push_back(std::move(s));
        }
        SplitLoop& s = splits[std::size_t(split_of[a])];
        auto on_f = [&, a = a, f = f](Index v) { return (face_mask(P.vertex_edge[v], D.loop_cell[a]) >> f) & 1; };
        for (std::size_t k = 0; k < s.pieces.size(); ++k) {
            const std::vector<Index> cyc = s.pieces[k];
            const int n = int(cyc.size());
            int seg[2], ns = 0;
            for (int i = 0; i < n && ns < 2; ++i)
                if (on_f(cyc[std::size_t(i)]) && on_f(cyc[std::size_t((i + 1) % n)])) seg[ns++] = i;
            if (ns < 2) continue;
            // Arcs cyc[seg0 + 1 .. seg1] and cyc[seg1 + 1 .. seg0 + n], each of two or more
            // crossings (the segments share none): a chord between their middles leaves
            // one segment on each side.
            const int len1 = seg[1] - seg[0], len2 = n - len1;
            const int ia = (seg[0] + 1 + len1 / 2) % n, ib = (seg[1] + 1 + len2 / 2) % n;
            std::vector<Index> p1, p2;
            for (int i = ia;; i = (i + 1) % n) {
                p1.push_back(cyc[std::size_t(i)]);
                if (i == ib) break;
            }
            for (int i = ib;; i = (i + 1) % n) {
                p2.push_back(cyc[std::size_t(i)]);
                if (i == ia) break;
            }
            s.pieces[k] = std::move(p1);
            s.pieces.push_back(std::move(p2));
            s.id.push_back(next_id++);
            break;
        }
    }
    // The crossings of every loop, the pieces' in place of their loops'.
    std::vector<Index> first(next_id + 1, 0), cross;
    cross.reserve(D.loop_cross.size() + 8 * splits.size());
    D.loop_cell.resize(next_id);
    std::vector<const std::vector<Index>*> piece(next_id, nullptr);
    for (const SplitLoop& s : splits)
        for (std::size_t k = 0; k < s.pieces.size(); ++k) {
            piece[s.id[k]] = &s.pieces[k];
            D.loop_cell[s.id[k]] = D.loop_cell[s.id[0]];
        }
    for (Index l = 0; l < next_id; ++l) {
        if (piece[l]) cross.insert(cross.end(), piece[l]->begin(), piece[l]->end());
        else
            cross.insert(cross.end(), D.loop_cross.begin() + D.loop_first[l],
                         D.loop_cross.begin() + D.loop_first[l + 1]);
        first[l + 1] = Index(cross.size());
    }
    D.loop_first = std::move(first);
    D.loop_cross = std::move(cross);
    return splits;
}

/// The pieces of cut loop s around its crossing v, in the order of v's fan: from the piece
/// holding the loop's edge out of v, across the chords at v, to the one holding the edge in.
int pieces_around(const SplitLoop& s, Index v, Index* out, int cap) {
    const std::size_t n = s.cycle.size();
    const std::size_t at = std::size_t(std::find(s.cycle.begin(), s.cycle.end(), v) - s.cycle.begin());
    if (at == n) return -1;
    const Index pred = s.cycle[(at + n - 1) % n];
    Index to = s.cycle[(at + 1) % n]; // the piece to emit holds the edge v -> to
    int k = 0;
    for (std::size_t guard = 0; guard <= s.pieces.size(); ++guard) {
        std::size_t found = s.pieces.size();
        Index back = kNoIndex;
        for (std::size_t p = 0; p < s.pieces.size() && found == s.pieces.size(); ++p) {
            const auto& c = s.pieces[p];
            for (std::size_t i = 0; i < c.size(); ++i)
                if (c[i] == v && c[(i + 1) % c.size()] == to) {
                    found = p;
                    back = c[(i + c.size() - 1) % c.size()];
                }
        }
        if (found == s.pieces.size() || k == cap) return -1;
        out[k++] = s.id[found];
        if (back == pred) return k;
        to = back; // a chord v - back: the next piece holds v -> back
    }
    return -1;
}

/// Splits the quad (a, b, c, d) along the diagonal whose two triangles bend least.
void split_quad(const std::vector<Vec3f>& x, const Index* q, std::array<Index, 3>* out) {
    auto normal = [&](Index i, Index j, Index k) { return normalize(cross(x[j] - x[i], x[k] - x[i])); };
    const float bend02 = dot(normal(q[0], q[1], q[2]), normal(q[0], q[2], q[3]));
    const float bend13 = dot(normal(q[0], q[1], q[3]), normal(q[1], q[2], q[3]));
    if (bend02 >= bend13) {
        out[0] = {q[0], q[1], q[2]};
        out[1] = {q[0], q[2], q[3]};
    } else {
        out[0] = {q[0], q[1], q[3]};
        out[1] = {q[1], q[2], q[3]};
    }
}

} // namespace

namespace {

/// The triangles of the dual mesh on the vertices that remain after merging (rep).
Mesh dual_triangles(const DualMesh& D, const std::vector<Index>& rep, const openvdb::math::Transform& xf,
                    std::size_t nv) {
    Mesh out;
    const std::size_t nloops = rep.size();
    std::vector<Index> id(nloops, kNoIndex);
    for (std::size_t l = 0; l < nloops; ++l) {
        if (rep[l] != l) continue;
        id[l] = Index(out.positions.size());
        const openvdb::Vec3d w = xf.indexToWorld(openvdb::Vec3d(D.vert[l].x, D.vert[l].y, D.vert[l].z));
        out.positions.emplace_back(float(w.x()), float(w.y()), float(w.z()));
    }
    out.triangles.reserve(2 * nv);
    for (std::size_t v = 0; v < nv; ++v) {
        Index poly[16];
        int k = 0;
        for (Index i = D.face_first[v]; i < D.face_first[v + 1]; ++i) {
            const Index u = id[rep[D.face_loops[i]]];
            if (k == 0 || poly[k - 1] != u) poly[k++] = u;
        }
        while (k > 1 && poly[k - 1] == poly[0]) --k;
        if (k < 3) continue;
        if (k == 4) {
            std::array<Index, 3> t[2];
            split_quad(out.positions, poly, t);
            out.triangles.push_back(t[0]);
            out.triangles.push_back(t[1]);
        } else {
            for (int i = 1; i + 1 < k; ++i) out.triangles.push_back({poly[0], poly[i], poly[i + 1]});
        }
    }
    return out;
}

/// Rounds of the crossing guard of the adaptive merge.
constexpr int kGuardRounds = 4;

} // namespace

Mesh dual_marching_cubes(const Volume& vol, const DualMcOptions& opt, DualMcStats* stats_out) {
    if (!vol.occupancy) throw Error("the volume has no occupancy grid");
    DualMcStats st;
    auto progress = [&](double f) {
        if (opt.progress) opt.progress(f);
    };
    // 1. Topology and crossings.
    MarchingCubesPatches P;
    MarchingCubesOptions mco = opt.mc;
    mco.progress = [&](double f) { progress(0.4 * f); };
    const Mesh mc = marching_cubes(vol, mco, &st.mc, &P);
    std::size_t nloops = P.loop_cell.size();
    const std::size_t nv = mc.positions.size();

    // 2. Normals; the crossings in index space.
    DualMesh D;
    D.cross_n = crossing_normals(vol, mc, P, opt.normals, opt.normal_px, st.normals);
    const auto& xf = vol.occupancy->transform();
    const openvdb::Vec3d w0 = xf.indexToWorld(openvdb::Vec3d(0, 0, 0));
    const double h = vol.voxel_size();
    D.cross_pos.resize(nv);
    for (std::size_t v = 0; v < nv; ++v) {
        const Vec3f& w = mc.positions[v];
        D.cross_pos[v] = Vec3d((w.x - w0.x()) / h, (w.y - w0.y()) / h, (w.z - w0.z()) / h);
    }
    progress(0.6);

    // 3. Each loop's crossings (its triangles are consecutive), loops cut where two would
    // share two edges, and each loop's vertex.
    const Fans fans = build_fans(mc);
    std::vector<int> split_of;
    std::vector<SplitLoop> splits;
    {
        std::vector<Index> tfirst(nloops + 1, Index(mc.triangles.size()));
        for (Index t = Index(mc.triangles.size()); t-- > 0;) tfirst[P.triangle_loop[t]] = t;
        D.loop_first.assign(nloops + 1, 0);
        D.loop_cross.reserve(nv * 4);
        for (std::size_t l = 0; l < nloops; ++l) {
            const std::size_t b = D.loop_cross.size();
            for (Index t = tfirst[l]; t < tfirst[l + 1]; ++t)
                for (Index v : mc.triangles[t])
                    if (P.vertex_edge[v][3] >= 0 && std::find(D.loop_cross.begin() + std::ptrdiff_t(b),
                                                              D.loop_cross.end(), v) == D.loop_cross.end())
                        D.loop_cross.push_back(v);
            D.loop_first[l + 1] = Index(D.loop_cross.size());
        }
        D.loop_cell = P.loop_cell;
        splits = split_shared_faces(mc, P, fans, tfirst, D, split_of);
    }
    const std::size_t nloops0 = nloops;
    nloops = D.loop_cell.size();
    st.cells = nloops;
    st.split_loops = splits.size();
    D.vert.resize(nloops);
    std::atomic<std::size_t> clamped{0}, multi{0};
    std::atomic<std::size_t> ranks[4] = {0, 0, 0, 0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nloops, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
        std::size_t my_clamped = 0, my_multi = 0, my_rank[4] = {0, 0, 0, 0};
        for (std::size_t l = r.begin(); l != r.end(); ++l) {
            Qef q;
            for (Index i = D.loop_first[l]; i < D.loop_first[l + 1]; ++i)
                q.add(D.cross_pos[D.loop_cross[i]], D.cross_n[D.loop_cross[i]]);
            const openvdb::Coord& c = D.loop_cell[l];
            const Qef::Result res = q.solve(Vec3d(c.x(), c.y(), c.z()), 1.0, opt.singular_ratio);
            D.vert[l] = res.x;
            my_clamped += res.clamped;
            ++my_rank[res.rank];
            if ((l > 0 && D.loop_cell[l - 1] == c) || (l + 1 < nloops && D.loop_cell[l + 1] == c)) ++my_multi;
        }
        clamped += my_clamped;
        multi += my_multi;
        for (int k = 0; k < 4; ++k) ranks[k] += my_rank[k];
    });
    st.clamped = clamped;
    st.multi_disc_cells = multi;
    for (int k = 0; k < 4; ++k) st.rank[k] = ranks[k];
    progress(0.7);

    // 4. One polygon per crossed edge: the loops around it.
    {
        // The loops around crossing v, a cut loop's pieces in its place.
        auto dual_ring = [&](Index v, Index* out, int cap) {
            if (splits.empty()) return ring(fans, P, v, out, cap);
            Index loops[16];
            const int n = ring(fans, P, v, loops, 16);
            if (n < 0) return n;
            int k = 0;
            for (int i = 0; i < n; ++i) {
                const int s = loops[i] < nloops0 ? split_of[loops[i]] : -1;
                if (s < 0) {
                    if (k == cap) return -1;
                    out[k++] = loops[i];
                    continue;
                }
                const int m = pieces_around(splits[std::size_t(s)], v, out + k, cap - k);
                if (m < 0) return -1;
                k += m;
            }
            return k;
        };
        D.face_first.assign(nv + 1, 0);
        std::atomic<std::size_t> bad{0};
        std::vector<std::uint8_t> count(nv, 0);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
            Index loops[16];
            for (std::size_t v = r.begin(); v != r.end(); ++v) {
                if (P.vertex_edge[v][3] < 0) continue;
                const int k = dual_ring(Index(v), loops, 16);
                if (k < 3) ++bad;
                else count[v] = std::uint8_t(k);
            }
        });
        if (bad)
            throw Error("dual marching cubes: " + std::to_string(std::size_t(bad)) +
                        " crossing(s) have fewer than three discs around them (internal error)");
        for (std::size_t v = 0; v < nv; ++v) D.face_first[v + 1] = D.face_first[v] + count[v];
        D.face_loops.resize(D.face_first.back());
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t v = r.begin(); v != r.end(); ++v)
                if (count[v]) dual_ring(Index(v), &D.face_loops[D.face_first[v]], count[v]);
        });
        for (std::size_t v = 0; v < nv; ++v) {
            if (count[v] == 4) ++st.quads;
            else if (count[v]) ++st.other_polygons;
        }
    }
    progress(0.8);

    // 5. Adaptivity: cells merged up the octree. A merge is checked against the polygons
    // around its own vertex only, so a coarse polygon can still cut through a surface
    // nearby (a thin part across a groove): the merged mesh is checked for crossing faces,
    // and the merges that made them are undone (their loops frozen) and the octree merged
    // again, until none is left or no merged vertex is involved.
    const std::vector<Vec3d> vert0 = D.vert;
    std::vector<char> frozen(nloops, 0);
    std::vector<Index> rep(nloops);
    Mesh out;
    for (int round = 0;; ++round) {
        for (std::size_t l = 0; l < nloops; ++l) rep[l] = Index(l);
        D.vert = vert0;
        if (opt.max_error > 0) {
            AdaptiveStats ast;
            merge_octree(D, opt.max_error, opt.singular_ratio, rep, ast, &frozen);
            st.merged = ast.merged;
            st.levels = ast.levels;
        }
        progress(0.9);
        out = dual_triangles(D, rep, xf, nv);
        if (!opt.guard || opt.max_error <= 0 || st.merged == 0 || round >= kGuardRounds) break;
        const std::vector<FacePair> pairs = find_self_intersections(out);
        if (pairs.empty()) break;
        // Output vertex -> its root loop; freeze every loop of the roots of crossing faces.
        std::vector<Index> root_of(out.positions.size(), kNoIndex);
        for (std::size_t l = 0, k = 0; l < nloops; ++l)
            if (rep[l] == l) root_of[k++] = Index(l);
        std::vector<char> hit(nloops, 0);
        for (const FacePair& fp : pairs)
            for (std::uint32_t f : fp)
                for (Index u : out.triangles[f]) hit[root_of[u]] = 1;
        std::size_t newly = 0;
        for (std::size_t l = 0; l < nloops; ++l)
            if (hit[rep[l]] && rep[l] != l) ++newly; // a merged loop (frozen ones never merge)
        for (std::size_t l = 0; l < nloops; ++l)
            if (hit[rep[l]]) frozen[l] = 1;
        if (newly == 0) break; // the crossings do not come from merges
        ++st.guard_rounds;
    }
    progress(1.0);
    if (stats_out) *stats_out = st;
    return out;
}

} // namespace cm
