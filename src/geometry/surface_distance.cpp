// See surface_distance.h. Per mesh, two closest-primitive grids from OpenVDB's
// meshToVolume (unsigned, points given in index space as its adapter wants): a fine one
// (voxel diag/256, band 6 voxels), a middle one (diag/128, band 10) and a coarse one
// (diag/32, band 40: 1.25 diagonals). A
// sample's distance is the exact point-triangle distance minimised over the triangles
// that the 4^3 voxels around it name, in the finest grid whose band holds it.
#include "surface_distance.h"

#include <openvdb/math/Proximity.h>
#include <openvdb/tools/MeshToVolume.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/error.h"

namespace cm {
namespace {

using openvdb::Coord;
using VVec = openvdb::Vec3d;

struct PrimGrid {
    openvdb::math::Transform::Ptr xf;
    openvdb::Int32Grid::Ptr prim;
};

PrimGrid primitive_grid(const Mesh& m, double voxel, float band) {
    PrimGrid g;
    g.xf = openvdb::math::Transform::createLinearTransform(voxel);
    std::vector<openvdb::Vec3s> pts;
    pts.reserve(m.positions.size());
    for (const auto& p : m.positions) {
        const VVec q = g.xf->worldToIndex(VVec(p.x, p.y, p.z));
        pts.emplace_back(float(q.x()), float(q.y()), float(q.z()));
    }
    std::vector<openvdb::Vec3I> tris;
    tris.reserve(m.triangles.size());
    for (const auto& t : m.triangles) tris.emplace_back(t[0], t[1], t[2]);
    const openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec3I> adapter(pts, tris);
    g.prim = openvdb::Int32Grid::create(-1);
    openvdb::tools::meshToVolume<openvdb::FloatGrid>(adapter, *g.xf, band, band,
                                                     openvdb::tools::UNSIGNED_DISTANCE_FIELD, g.prim.get());
    return g;
}

struct Target {
    const Mesh* mesh = nullptr;
    PrimGrid level[3];
    double reach = 0;
};

double triangle_distance(const Mesh& m, std::int32_t k, const VVec& p) {
    const auto& t = m.triangles[std::size_t(k)];
    const auto v = [&](int i) {
        const Vec3f& q = m.positions[t[std::size_t(i)]];
        return VVec(q.x, q.y, q.z);
    };
    VVec uvw;
    return (openvdb::math::closestPointOnTriangleToPoint(v(0), v(1), v(2), p, uvw) - p).length();
}

// The exact distance to the nearest of the triangles that the 4^3 voxels around p name,
// or -1 when one of the 8 corners of p's cell is outside the grid's band.
double nearest_named(const Mesh& m, const PrimGrid& g, openvdb::Int32Grid::ConstAccessor& acc, const VVec& p) {
    const VVec q = g.xf->worldToIndex(p);
    const Coord c(int(std::floor(q.x())), int(std::floor(q.y())), int(std::floor(q.z())));
    double best = -1;
    for (int dx = -1; dx <= 2; ++dx)
        for (int dy = -1; dy <= 2; ++dy)
            for (int dz = -1; dz <= 2; ++dz) {
                std::int32_t prim = -1;
                const bool inner = dx >= 0 && dx <= 1 && dy >= 0 && dy <= 1 && dz >= 0 && dz <= 1;
                if (!acc.probeValue(c.offsetBy(dx, dy, dz), prim) || prim < 0) {
                    if (inner) return -1;
                    continue;
                }
                const double d = triangle_distance(m, prim, p);
                if (best < 0 || d < best) best = d;
            }
    return best;
}

struct Sum {
    double sum = 0;
    std::size_t beyond = 0;
};

// Mean distance of `n` area-weighted samples of `a` to the target mesh.
Sum mean_distance(const Mesh& a, const Target& t, int n, unsigned seed) {
    std::vector<double> cum;
    cum.reserve(a.triangles.size());
    double area = 0;
    for (const auto& f : a.triangles) {
        const Vec3f p = a.positions[f[0]], q = a.positions[f[1]], r = a.positions[f[2]];
        area += 0.5 * length(cross(cm::Vec3d(q - p), cm::Vec3d(r - p)));
        cum.push_back(area);
    }
    if (!(area > 0)) throw Error("surface_distance: a mesh has no area");
    // The samples are drawn serially (one seed, one sequence), measured in parallel.
    std::vector<VVec> pts(std::size_t(std::max(n, 0)));
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    for (auto& x : pts) {
        const std::size_t k = std::size_t(std::lower_bound(cum.begin(), cum.end(), u(rng) * area) - cum.begin());
        const auto& f = a.triangles[std::min(k, a.triangles.size() - 1)];
        double s = u(rng), w = u(rng);
        if (s + w > 1) s = 1 - s, w = 1 - w;
        const VVec p(a.positions[f[0]].x, a.positions[f[0]].y, a.positions[f[0]].z);
        const VVec q(a.positions[f[1]].x, a.positions[f[1]].y, a.positions[f[1]].z);
        const VVec r(a.positions[f[2]].x, a.positions[f[2]].y, a.positions[f[2]].z);
        x = p + (q - p) * s + (r - p) * w;
    }
    return tbb::parallel_deterministic_reduce(
        tbb::blocked_range<std::size_t>(0, pts.size(), 512), Sum{},
        [&](const tbb::blocked_range<std::size_t>& r, Sum s) {
            openvdb::Int32Grid::ConstAccessor acc[3] = {t.level[0].prim->getConstAccessor(),
                                                        t.level[1].prim->getConstAccessor(),
                                                        t.level[2].prim->getConstAccessor()};
            for (std::size_t i = r.begin(); i != r.end(); ++i) {
                double d = -1;
                for (int l = 0; l < 3 && d < 0; ++l) d = nearest_named(*t.mesh, t.level[l], acc[l], pts[i]);
                if (d < 0 || d > t.reach) {
                    d = t.reach;
                    ++s.beyond;
                }
                s.sum += d;
            }
            return s;
        },
        [](Sum a, const Sum& b) {
            a.sum += b.sum;
            a.beyond += b.beyond;
            return a;
        });
}

Target make_target(const Mesh& m, double diag) {
    Target t;
    t.mesh = &m;
    t.level[0] = primitive_grid(m, diag / 256.0, 6.0f);
    t.level[1] = primitive_grid(m, diag / 128.0, 10.0f);
    t.level[2] = primitive_grid(m, diag / 32.0, 40.0f);
    t.reach = 1.25 * diag;
    return t;
}

} // namespace

SurfaceDistance surface_distance(const Mesh& recon, const Mesh& truth, int samples) {
    if (recon.triangles.empty()) throw Error("surface_distance: the reconstruction has no triangles");
    if (truth.triangles.empty()) throw Error("surface_distance: the true model has no triangles");
    Vec3f lo, hi;
    truth.bounds(lo, hi);
    SurfaceDistance r;
    r.diag = length(cm::Vec3d(hi - lo));
    if (!(r.diag > 0)) throw Error("surface_distance: the true model has an empty bounding box");
    const Sum rt = mean_distance(recon, make_target(truth, r.diag), samples, 7);
    const Sum tr = mean_distance(truth, make_target(recon, r.diag), samples, 11);
    r.recon_to_true = rt.sum / samples;
    r.true_to_recon = tr.sum / samples;
    r.mean = 0.5 * (r.recon_to_true + r.true_to_recon);
    r.mean_pct = 100.0 * r.mean / r.diag;
    r.beyond_reach = rt.beyond + tr.beyond;
    return r;
}

} // namespace cm
