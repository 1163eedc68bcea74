#include "core/mesh_smooth.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "core/hull_distance.h"
#include "core/mesh_adjacency.h"

namespace cm {

namespace {

constexpr int kBisections = 8;

// One Jacobi step: dst[v] = src[v] + w * (mean of src over v's neighbours - src[v]).
// With a hull, the step is shortened so that |hull distance| stays within the
// tolerance (or does not grow, for a vertex that starts outside the band).
std::size_t relax(const VertexAdjacency& adj, const std::vector<Vec3f>& src, std::vector<Vec3f>& dst, double w,
                  const HullDistance* hull, double tol) {
    const std::size_t nv = src.size();
    std::atomic<std::size_t> clamped{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 2048), [&](const tbb::blocked_range<std::size_t>& r) {
        std::size_t local = 0;
        for (std::size_t v = r.begin(); v != r.end(); ++v) {
            const std::uint32_t b = adj.offsets[v], e = adj.offsets[v + 1];
            const Vec3f p = src[v];
            if (b == e) { dst[v] = p; continue; }
            Vec3f sum{0, 0, 0};
            for (std::uint32_t i = b; i < e; ++i) sum += src[adj.neighbours[i]];
            const Vec3f step = (sum * (1.0f / float(e - b)) - p) * float(w);
            if (!hull) { dst[v] = p + step; continue; }
            const Vec3d p0(p), s(step);
            const double h1 = (*hull)(p0 + s);
            if (std::fabs(h1) <= tol) { dst[v] = p + step; continue; }
            const double bound = std::max(tol, std::fabs((*hull)(p0)));
            if (std::fabs(h1) <= bound) { dst[v] = p + step; continue; }
            double lo = 0, hi = 1;
            for (int k = 0; k < kBisections; ++k) {
                const double mid = 0.5 * (lo + hi);
                if (std::fabs((*hull)(p0 + s * mid)) <= bound) lo = mid; else hi = mid;
            }
            dst[v] = p + step * float(lo);
            ++local;
        }
        clamped += local;
    });
    return clamped.load();
}

} // namespace

SmoothStats smooth_mesh(Mesh& mesh, const SmoothOptions& opt) {
    SmoothStats stats;
    if (mesh.positions.empty() || opt.iterations <= 0) return stats;
    const VertexAdjacency adj = build_vertex_adjacency(mesh);
    std::vector<Vec3f> a = std::move(mesh.positions), b(a.size());
    const double tol = opt.tolerance;
    for (int it = 0; it < opt.iterations; ++it) {
        if (opt.method == SmoothOptions::Method::Laplacian) {
            stats.clamped_steps += relax(adj, a, b, opt.factor, opt.hull, tol);
            a.swap(b);
        } else {
            stats.clamped_steps += relax(adj, a, b, opt.lambda, opt.hull, tol);
            stats.clamped_steps += relax(adj, b, a, opt.mu, opt.hull, tol);
        }
        if (opt.progress) opt.progress(double(it + 1) / opt.iterations);
    }
    mesh.positions = std::move(a);
    if (opt.hull) {
        stats.max_hull_distance = tbb::parallel_reduce(
            tbb::blocked_range<std::size_t>(0, mesh.positions.size(), 4096), 0.0,
            [&](const tbb::blocked_range<std::size_t>& r, double m) {
                for (std::size_t v = r.begin(); v != r.end(); ++v)
                    if (adj.degree(std::uint32_t(v)) > 0)
                        m = std::max(m, std::fabs((*opt.hull)(Vec3d(mesh.positions[v]))));
                return m;
            },
            [](double x, double y) { return std::max(x, y); });
    }
    if (!mesh.normals.empty()) mesh.compute_normals();
    return stats;
}

} // namespace cm
