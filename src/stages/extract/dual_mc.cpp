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
#include <Eigen/Dense>

#include "core/error.h"
#include "geometry/hull_normal.h"

namespace cm {
namespace {

using Index = std::uint32_t;

/// The Hermite normals of the crossings (one per Marching Cubes vertex, zero for centre vertices).
std::vector<Vec3f> crossing_normals(const Volume& vol, const Mesh& mc, const MarchingCubesPatches& P,
                                    DualMcOptions::Normals mode, const char*& source) {
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
                    const Vec3d n = hull_normal(*hull, Vec3d(mc.positions[v])).normal;
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

/// The vertex of one disc: the QEF minimum of its crossings (index space), clamped into its cell.
struct QefResult {
    Vec3d x;
    int rank = 0;
    bool clamped = false;
};

QefResult solve_qef(const Vec3d* p, const Vec3f* n, int count, const openvdb::Coord& cell, double singular_ratio) {
    Vec3d mean{};
    for (int i = 0; i < count; ++i) mean += p[i];
    mean = mean / double(count);
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    for (int i = 0; i < count; ++i) {
        const Eigen::Vector3d ni(n[i].x, n[i].y, n[i].z);
        const Vec3d d = p[i] - mean;
        A += ni * ni.transpose();
        b += ni * ni.dot(Eigen::Vector3d(d.x, d.y, d.z));
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(A);
    const Eigen::Vector3d ev = es.eigenvalues();
    const double top = std::max({ev[0], ev[1], ev[2], 0.0});
    Eigen::Vector3d y = Eigen::Vector3d::Zero();
    QefResult r;
    if (top > 0) {
        const Eigen::Matrix3d V = es.eigenvectors();
        for (int k = 0; k < 3; ++k) {
            if (ev[k] <= singular_ratio * top) continue;
            y += V.col(k) * (V.col(k).dot(b) / ev[k]);
            ++r.rank;
        }
    }
    r.x = mean + Vec3d(y[0], y[1], y[2]);
    // Clamped into the cell, a hair inside, so vertices of neighbouring cells never coincide.
    constexpr double kMargin = 1e-3;
    for (int a = 0; a < 3; ++a) {
        const double lo = cell[a] + kMargin, hi = cell[a] + 1 - kMargin;
        if (r.x[a] < lo || r.x[a] > hi) r.clamped = true;
        r.x[a] = std::clamp(r.x[a], lo, hi);
    }
    return r;
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
    const std::size_t nloops = P.loop_cell.size();
    st.cells = nloops;

    // 2. Normals.
    const std::vector<Vec3f> N = crossing_normals(vol, mc, P, opt.normals, st.normals);
    progress(0.6);

    // 3. One vertex per loop. A loop's triangles are consecutive.
    const auto& xf = vol.occupancy->transform();
    const openvdb::Vec3d w0 = xf.indexToWorld(openvdb::Vec3d(0, 0, 0));
    const double h = vol.voxel_size();
    auto to_index = [&](const Vec3f& w) { return Vec3d((w.x - w0.x()) / h, (w.y - w0.y()) / h, (w.z - w0.z()) / h); };
    std::vector<Index> loop_first(nloops + 1, Index(mc.triangles.size()));
    for (Index t = Index(mc.triangles.size()); t-- > 0;) loop_first[P.triangle_loop[t]] = t;
    Mesh out;
    out.positions.resize(nloops);
    std::atomic<std::size_t> clamped{0}, multi{0};
    std::atomic<std::size_t> ranks[4] = {0, 0, 0, 0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nloops, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
        std::size_t my_clamped = 0, my_multi = 0, my_rank[4] = {0, 0, 0, 0};
        for (std::size_t l = r.begin(); l != r.end(); ++l) {
            Index ids[40];
            int n = 0;
            for (Index t = loop_first[l]; t < loop_first[l + 1]; ++t)
                for (Index v : mc.triangles[t])
                    if (P.vertex_edge[v][3] >= 0 && std::find(ids, ids + n, v) == ids + n && n < 40) ids[n++] = v;
            Vec3d p[40];
            Vec3f nn[40];
            for (int i = 0; i < n; ++i) p[i] = to_index(mc.positions[ids[i]]), nn[i] = N[ids[i]];
            const QefResult q = solve_qef(p, nn, n, P.loop_cell[l], opt.singular_ratio);
            const openvdb::Vec3d w = xf.indexToWorld(openvdb::Vec3d(q.x.x, q.x.y, q.x.z));
            out.positions[l] = Vec3f(float(w.x()), float(w.y()), float(w.z()));
            my_clamped += q.clamped;
            ++my_rank[q.rank];
            if ((l > 0 && P.loop_cell[l - 1] == P.loop_cell[l]) ||
                (l + 1 < nloops && P.loop_cell[l + 1] == P.loop_cell[l]))
                ++my_multi;
        }
        clamped += my_clamped;
        multi += my_multi;
        for (int k = 0; k < 4; ++k) ranks[k] += my_rank[k];
    });
    st.clamped = clamped;
    st.multi_disc_cells = multi;
    for (int k = 0; k < 4; ++k) st.rank[k] = ranks[k];
    progress(0.75);

    // 4. One polygon per crossed edge: count, then write.
    const Fans fans = build_fans(mc);
    const std::size_t nv = mc.positions.size();
    std::vector<Index> tri_first(nv + 1, 0);
    std::atomic<std::size_t> bad{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        Index loops[16];
        for (std::size_t v = r.begin(); v != r.end(); ++v) {
            if (P.vertex_edge[v][3] < 0) continue;
            const int k = ring(fans, P, Index(v), loops, 16);
            if (k < 3) ++bad;
            else tri_first[v + 1] = Index(k - 2);
        }
    });
    if (bad)
        throw Error("dual marching cubes: " + std::to_string(std::size_t(bad)) +
                    " crossing(s) have fewer than three discs around them (internal error)");
    for (std::size_t v = 0; v < nv; ++v) tri_first[v + 1] += tri_first[v];
    out.triangles.resize(tri_first.back());
    std::atomic<std::size_t> quads{0}, other{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        Index loops[16];
        std::size_t my_quads = 0, my_other = 0;
        for (std::size_t v = r.begin(); v != r.end(); ++v) {
            const Index t0 = tri_first[v], nt = tri_first[v + 1] - t0;
            if (nt == 0) continue;
            const int k = ring(fans, P, Index(v), loops, 16);
            if (k == 4) {
                split_quad(out.positions, loops, &out.triangles[t0]);
                ++my_quads;
            } else {
                for (int i = 1; i + 1 < k; ++i) out.triangles[t0 + Index(i - 1)] = {loops[0], loops[i], loops[i + 1]};
                ++my_other;
            }
        }
        quads += my_quads;
        other += my_other;
    });
    st.quads = quads;
    st.other_polygons = other;
    progress(1.0);
    if (stats_out) *stats_out = st;
    return out;
}

} // namespace cm
