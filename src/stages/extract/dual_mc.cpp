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
#include "dual_mc.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "dmc_octree.h"
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
    const std::size_t nloops = P.loop_cell.size(), nv = mc.positions.size();
    st.cells = nloops;

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

    // 3. Each loop's crossings (its triangles are consecutive), and its vertex.
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
    }
    D.loop_cell = std::move(P.loop_cell);
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
        const Fans fans = build_fans(mc);
        D.face_first.assign(nv + 1, 0);
        std::atomic<std::size_t> bad{0};
        std::vector<std::uint8_t> count(nv, 0);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
            Index loops[16];
            for (std::size_t v = r.begin(); v != r.end(); ++v) {
                if (P.vertex_edge[v][3] < 0) continue;
                const int k = ring(fans, P, Index(v), loops, 16);
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
                if (count[v]) ring(fans, P, Index(v), &D.face_loops[D.face_first[v]], count[v]);
        });
        for (std::size_t v = 0; v < nv; ++v) {
            if (count[v] == 4) ++st.quads;
            else if (count[v]) ++st.other_polygons;
        }
    }
    progress(0.8);

    // 5. Adaptivity: cells merged up the octree.
    std::vector<Index> rep(nloops);
    for (std::size_t l = 0; l < nloops; ++l) rep[l] = Index(l);
    if (opt.max_error > 0) {
        AdaptiveStats ast;
        merge_octree(D, opt.max_error, opt.singular_ratio, rep, ast);
        st.merged = ast.merged;
        st.levels = ast.levels;
    }
    progress(0.9);

    // 6. The triangles, on the vertices that remain.
    Mesh out;
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
    progress(1.0);
    if (stats_out) *stats_out = st;
    return out;
}

} // namespace cm
