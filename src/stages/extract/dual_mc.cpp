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
// 5. Adaptivity: cells merged up an octree into one vertex where it represents them
//    (dmc_octree.h), merges undone where their polygons cross another part of the surface.
//
// Loops that would share two edges are cut in pieces first (dmc_loops.h).
#include "dual_mc.h"

#include "geometry/mesh_intersect.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <optional>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "dmc_loops.h"
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
        if (vol.views && !vol.views->views.empty())
            hull = carved_hull(*vol.occupancy, *vol.views, vol.silhouette_tables);
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

/// Splits the quad (a, b, c, d) along the diagonal whose two triangles bend least, or along
/// the other one when `other` (the crossing guard's choice where the first crossed a face).
void split_quad(const std::vector<Vec3f>& x, const Index* q, bool other, std::array<Index, 3>* out) {
    auto normal = [&](Index i, Index j, Index k) { return normalize(cross(x[j] - x[i], x[k] - x[i])); };
    const float bend02 = dot(normal(q[0], q[1], q[2]), normal(q[0], q[2], q[3]));
    const float bend13 = dot(normal(q[0], q[1], q[3]), normal(q[1], q[2], q[3]));
    if ((bend02 >= bend13) != other) {
        out[0] = {q[0], q[1], q[2]};
        out[1] = {q[0], q[2], q[3]};
    } else {
        out[0] = {q[0], q[1], q[3]};
        out[1] = {q[1], q[2], q[3]};
    }
}

/// The triangles of the dual mesh on the vertices that remain after merging (rep), quads
/// split the other way where `other` says so; `crossing_of` gets each triangle's crossing.
Mesh dual_triangles(const DualMesh& D, const std::vector<Index>& rep, const openvdb::math::Transform& xf,
                    std::size_t nv, const std::vector<char>& other, std::vector<Index>& crossing_of) {
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
    crossing_of.clear();
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
            split_quad(out.positions, poly, other[v] != 0, t);
            out.triangles.push_back(t[0]);
            out.triangles.push_back(t[1]);
        } else {
            for (int i = 1; i + 1 < k; ++i) out.triangles.push_back({poly[0], poly[i], poly[i + 1]});
        }
        crossing_of.resize(out.triangles.size(), Index(v));
    }
    return out;
}

/// Rounds of the crossing guard (merges undone, vertices put at their mass point, quads
/// split the other way).
constexpr int kGuardRounds = 8;

/// The steps of dual_marching_cubes (see the top of the file), over the dual mesh they make.
class DualContouring {
public:
    DualContouring(const Volume& vol, const DualMcOptions& opt, DualMcStats& st)
        : vol_(vol), opt_(opt), st_(st), xf_(vol.occupancy->transform()) {}

    /// 1. Topology and crossings: the Marching Cubes loops.
    void topology(const Progress& progress) {
        mc_ = marching_cubes_loops(vol_, opt_.mc, progress);
        st_.mc = mc_.stats;
        nv_ = mc_.mesh.positions.size();
    }
    /// 2. Normals; the crossings in index space.
    void crossings();
    /// 3. Each loop's crossings, loops cut where two would share two edges, and each loop's vertex.
    void loop_vertices();
    /// 4. One polygon per crossed edge: the loops around it.
    void polygons();
    /// 5. Adaptivity: the triangles of the dual mesh, cells merged up the octree. Reports 0.9
    /// of `progress` (the whole run's) each round.
    Mesh merge(const Progress& progress);

private:
    /// Per loop: whether a vertex of `out`'s crossing faces `pairs` stands for it.
    std::vector<char> loops_hit(const Mesh& out, const std::vector<FacePair>& pairs,
                                const std::vector<Index>& rep) const;
    /// Freezes every loop of the merged vertices that `out`'s crossing faces `pairs` touch;
    /// returns the merged loops among them.
    std::size_t freeze_crossings(const Mesh& out, const std::vector<FacePair>& pairs, const std::vector<Index>& rep,
                                 std::vector<char>& frozen) const;
    /// Puts the vertex (in `vert`) of every loop that `pairs` touch, and is not there yet, at
    /// the mass point of its crossings; returns how many moved.
    std::size_t relax_crossings(const Mesh& out, const std::vector<FacePair>& pairs, const std::vector<Index>& rep,
                                std::vector<char>& relaxed, std::vector<Vec3d>& vert) const;

    const Volume& vol_;
    const DualMcOptions& opt_;
    DualMcStats& st_;
    const openvdb::math::Transform& xf_;
    MarchingCubesLoops mc_;
    std::size_t nv_ = 0; ///< crossings (Marching Cubes vertices)
    DualMesh D_;
    std::optional<dmc::DualLoops> loops_;
};

void DualContouring::crossings() {
    D_.cross_n = crossing_normals(vol_, mc_.mesh, mc_.patches, opt_.normals, opt_.normal_px, st_.normals);
    const openvdb::Vec3d w0 = xf_.indexToWorld(openvdb::Vec3d(0, 0, 0));
    const double h = vol_.voxel_size();
    D_.cross_pos.resize(nv_);
    for (std::size_t v = 0; v < nv_; ++v) {
        const Vec3f& w = mc_.mesh.positions[v];
        D_.cross_pos[v] = Vec3d((w.x - w0.x()) / h, (w.y - w0.y()) / h, (w.z - w0.z()) / h);
    }
}

void DualContouring::loop_vertices() {
    loops_.emplace(mc_.mesh, mc_.patches, D_);
    const std::size_t nloops = D_.loop_cell.size();
    st_.cells = nloops;
    st_.split_loops = loops_->cut();
    D_.vert.resize(nloops);
    std::atomic<std::size_t> clamped{0}, multi{0};
    std::atomic<std::size_t> ranks[4] = {0, 0, 0, 0};
    const DualMesh& D = D_;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nloops, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
        std::size_t my_clamped = 0, my_multi = 0, my_rank[4] = {0, 0, 0, 0};
        for (std::size_t l = r.begin(); l != r.end(); ++l) {
            Qef q;
            for (Index i = D.loop_first[l]; i < D.loop_first[l + 1]; ++i)
                q.add(D.cross_pos[D.loop_cross[i]], D.cross_n[D.loop_cross[i]]);
            const openvdb::Coord& c = D.loop_cell[l];
            const Qef::Result res = q.solve(Vec3d(c.x(), c.y(), c.z()), 1.0, opt_.singular_ratio);
            D_.vert[l] = res.x;
            my_clamped += res.clamped;
            ++my_rank[res.rank];
            if ((l > 0 && D.loop_cell[l - 1] == c) || (l + 1 < nloops && D.loop_cell[l + 1] == c)) ++my_multi;
        }
        clamped += my_clamped;
        multi += my_multi;
        for (int k = 0; k < 4; ++k) ranks[k] += my_rank[k];
    });
    st_.clamped = clamped;
    st_.multi_disc_cells = multi;
    for (int k = 0; k < 4; ++k) st_.rank[k] = ranks[k];
}

void DualContouring::polygons() {
    const auto& edge = mc_.patches.vertex_edge;
    const dmc::DualLoops& loops = *loops_;
    D_.face_first.assign(nv_ + 1, 0);
    std::atomic<std::size_t> bad{0};
    std::vector<std::uint8_t> count(nv_, 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv_, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        Index around[16];
        for (std::size_t v = r.begin(); v != r.end(); ++v) {
            if (edge[v][3] < 0) continue;
            const int k = loops.around(Index(v), around, 16);
            if (k < 3) ++bad;
            else count[v] = std::uint8_t(k);
        }
    });
    if (bad)
        throw Error("dual marching cubes: " + std::to_string(std::size_t(bad)) +
                    " crossing(s) have fewer than three discs around them (internal error)");
    for (std::size_t v = 0; v < nv_; ++v) D_.face_first[v + 1] = D_.face_first[v] + count[v];
    D_.face_loops.resize(D_.face_first.back());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv_, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t v = r.begin(); v != r.end(); ++v)
            if (count[v]) loops.around(Index(v), &D_.face_loops[D_.face_first[v]], count[v]);
    });
    for (std::size_t v = 0; v < nv_; ++v) {
        if (count[v] == 4) ++st_.quads;
        else if (count[v]) ++st_.other_polygons;
    }
}

// The dual mesh is checked for crossing faces, and the guard removes them where they come
// from, in rounds until none is left:
// - a merge is checked against the polygons around its own vertex only, so a coarse polygon
//   can still cut through a surface nearby (a thin part across a groove): merges that made
//   crossing faces are undone (their loops frozen) and the octree merged again;
// - a QEF minimum can stray from its disc where the normals disagree with the crossings (a
//   thin part, a part one cell across, the views' normals at a wobbly outline) and meet the
//   vertex of a disc beside it, even within one cell (seen on drawn outlines at resolution
//   256): the vertices of crossing faces go back to the mass point of their crossings, which
//   lies inside their disc's cell among its crossings;
// - what still crosses after that is a quad split along the wrong diagonal: split the other
//   way.
Mesh DualContouring::merge(const Progress& progress) {
    const std::size_t nloops = D_.loop_cell.size();
    std::vector<Vec3d> vert0 = D_.vert;
    std::vector<char> frozen(nloops, 0), relaxed(nloops, 0), other(nv_, 0);
    std::vector<Index> rep(nloops), crossing_of;
    Mesh out;
    for (int round = 0;; ++round) {
        for (std::size_t l = 0; l < nloops; ++l) rep[l] = Index(l);
        D_.vert = vert0;
        if (opt_.max_error > 0) {
            AdaptiveStats ast;
            merge_octree(D_, opt_.max_error, opt_.singular_ratio, rep, ast, &frozen);
            st_.merged = ast.merged;
            st_.levels = ast.levels;
        }
        progress(0.9);
        out = dual_triangles(D_, rep, xf_, nv_, other, crossing_of);
        if (!opt_.guard) break;
        const std::vector<FacePair> pairs = find_self_intersections(out);
        st_.crossings_left = pairs.size();
        if (pairs.empty() || round >= kGuardRounds) break;
        ++st_.guard_rounds;
        if (st_.merged && freeze_crossings(out, pairs, rep, frozen)) continue;
        if (const std::size_t moved = relax_crossings(out, pairs, rep, relaxed, vert0)) {
            st_.relaxed += moved;
            continue;
        }
        std::size_t flipped = 0;
        for (const FacePair& fp : pairs)
            for (std::uint32_t f : fp) {
                const Index v = crossing_of[f];
                if (D_.face_first[v + 1] - D_.face_first[v] == 4 && !other[v]) other[v] = 1, ++flipped;
            }
        st_.flipped += flipped;
        if (!flipped) break;
    }
    return out;
}

std::vector<char> DualContouring::loops_hit(const Mesh& out, const std::vector<FacePair>& pairs,
                                            const std::vector<Index>& rep) const {
    const std::size_t nloops = rep.size();
    // Output vertex -> its root loop; then every loop of the roots of crossing faces.
    std::vector<Index> root_of(out.positions.size(), kNoIndex);
    for (std::size_t l = 0, k = 0; l < nloops; ++l)
        if (rep[l] == l) root_of[k++] = Index(l);
    std::vector<char> root_hit(nloops, 0), hit(nloops, 0);
    for (const FacePair& fp : pairs)
        for (std::uint32_t f : fp)
            for (Index u : out.triangles[f]) root_hit[root_of[u]] = 1;
    for (std::size_t l = 0; l < nloops; ++l) hit[l] = root_hit[rep[l]];
    return hit;
}

std::size_t DualContouring::freeze_crossings(const Mesh& out, const std::vector<FacePair>& pairs,
                                             const std::vector<Index>& rep, std::vector<char>& frozen) const {
    const std::vector<char> hit = loops_hit(out, pairs, rep);
    std::size_t newly = 0;
    for (std::size_t l = 0; l < rep.size(); ++l)
        if (hit[l] && rep[l] != l) ++newly; // a merged loop (frozen ones never merge)
    for (std::size_t l = 0; l < rep.size(); ++l)
        if (hit[l]) frozen[l] = 1;
    return newly;
}

std::size_t DualContouring::relax_crossings(const Mesh& out, const std::vector<FacePair>& pairs,
                                            const std::vector<Index>& rep, std::vector<char>& relaxed,
                                            std::vector<Vec3d>& vert) const {
    const std::vector<char> hit = loops_hit(out, pairs, rep);
    std::size_t moved = 0;
    for (std::size_t l = 0; l < rep.size(); ++l) {
        if (!hit[l] || relaxed[l]) continue;
        Vec3d sum{};
        for (Index i = D_.loop_first[l]; i < D_.loop_first[l + 1]; ++i) sum += D_.cross_pos[D_.loop_cross[i]];
        vert[l] = sum / double(D_.loop_first[l + 1] - D_.loop_first[l]);
        relaxed[l] = 1;
        ++moved;
    }
    return moved;
}

} // namespace

Result<Mesh, DualMcStats> dual_marching_cubes(const Volume& vol, const DualMcOptions& opt, Progress progress) {
    if (!vol.occupancy) throw Error("the volume has no occupancy grid");
    Result<Mesh, DualMcStats> r;
    DualContouring dc(vol, opt, r.stats);
    dc.topology(progress.part(0.0, 0.4));
    dc.crossings();
    progress(0.6);
    dc.loop_vertices();
    progress(0.7);
    dc.polygons();
    progress(0.8);
    r.value = dc.merge(progress);
    progress(1.0);
    return r;
}

void DualMcOptions::declare(ParamBinder& b) {
    b.add(normals,
          ParamSpec::Enum("normals", "auto", {"auto", "views", "mesh"},
                          "crossing normals: auto uses the volume's stored normals, else the views' outlines "
                          "(exact), else mesh; views requires the views; mesh approximates them from the "
                          "Marching Cubes surface"),
          {Normals::Auto, Normals::Views, Normals::Mesh});
    b.add(normal_px, ParamSpec::Float("normal_px", 3.0, 0.0, 64.0, "px",
                                      "normals from the views: the outline's direction averaged over a disc of this "
                                      "radius (follows the drawn shape, not a mask's pixel steps); 0: at the point"));
    b.add(max_error, ParamSpec::Float("max_error", 0.2, 0.0, 16.0, "cell",
                                      "adaptivity: cells merge up an octree into one vertex while it stays within "
                                      "this distance of every crossing's tangent plane and the topology is kept; 0: "
                                      "one vertex per disc of every cell"));
    b.add(singular_ratio, ParamSpec::Float("singular_ratio", 0.1, 0.0, 1.0, "",
                                           "QEF eigenvalues below this fraction of the largest are dropped: larger "
                                           "keeps vertices of weakly curved patches near the crossings' mean, "
                                           "smaller sharpens"));
    mc.declare_ambiguity(b, "ambiguous cell faces, as extract.marching_cubes");
    mc.declare_thin_parts(b);
}

void DualMcStats::report(Metrics& m) const {
    m.count("quads", quads);
    m.count("other_polygons", other_polygons);
    m.count("multi_disc_cells", multi_disc_cells);
    m.count("split_loops", split_loops);
    m.count("clamped", clamped);
    m.count("flat_vertices", rank[1]);
    m.count("crease_vertices", rank[2]);
    m.count("corner_vertices", rank[3]);
    m.metric("normals", normals);
    m.count("merged", merged);
    m.metric("levels", double(levels));
    m.metric("guard_rounds", double(guard_rounds));
    m.count("guard_relaxed", relaxed);
    m.count("guard_flipped", flipped);
    if (crossings_left)
        m.warn(std::to_string(crossings_left) + " pairs of faces cross each other in the extracted mesh, more than " +
               "the guard could remove (mesh.write will refuse them)");
    m.count("thin_points", mc.thin_points);
    if (mc.missing_crossings)
        m.warn(std::to_string(mc.missing_crossings) +
               " crossed edge(s) have no crossing in the refined volume; their crossings sit at the edge midpoint");
}

} // namespace cm
