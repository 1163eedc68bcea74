#include "core/mesh_intersect.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <unordered_map>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace cm {

namespace {

// Does the segment [p, q] cross triangle (a, b, c) at a point strictly inside both?
bool segment_crosses(const Vec3d& p, const Vec3d& q, const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    const Vec3d d = q - p, e1 = b - a, e2 = c - a;
    const Vec3d h = cross(d, e2);
    const double det = dot(e1, h);
    const double scale = length(d) * length(e1) * length(e2);
    if (std::fabs(det) <= 1e-12 * scale) return false;   // parallel or coplanar
    const double inv = 1.0 / det;
    const Vec3d s = p - a;
    const double u = dot(s, h) * inv;
    if (u <= 1e-9 || u >= 1 - 1e-9) return false;
    const Vec3d qv = cross(s, e1);
    const double v = dot(d, qv) * inv;
    if (v <= 1e-9 || u + v >= 1 - 1e-9) return false;
    const double t = dot(e2, qv) * inv;
    return t > 1e-9 && t < 1 - 1e-9;
}

} // namespace

std::size_t count_self_intersections(const Mesh& m) {
    const std::size_t nf = m.triangles.size();
    if (nf < 2) return 0;
    std::vector<Vec3d> lo(nf), hi(nf);
    double edge_sum = 0;
    for (std::size_t f = 0; f < nf; ++f) {
        const auto& t = m.triangles[f];
        const Vec3d a(m.positions[t[0]]), b(m.positions[t[1]]), c(m.positions[t[2]]);
        lo[f] = vmin(a, vmin(b, c));
        hi[f] = vmax(a, vmax(b, c));
        edge_sum += length(b - a);
    }
    Vec3d glo = lo[0], ghi = hi[0];
    for (std::size_t f = 1; f < nf; ++f) { glo = vmin(glo, lo[f]); ghi = vmax(ghi, hi[f]); }
    const double cell = std::max(2.0 * edge_sum / double(nf), 1e-12);
    auto key = [&](int i, int j, int k) {
        return (std::uint64_t(std::uint32_t(i) & 0x1fffff) << 42) | (std::uint64_t(std::uint32_t(j) & 0x1fffff) << 21) |
               std::uint64_t(std::uint32_t(k) & 0x1fffff);
    };
    auto cell_of = [&](double x, double o) { return int(std::floor((x - o) / cell)); };
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;
    grid.reserve(nf);
    for (std::size_t f = 0; f < nf; ++f)
        for (int i = cell_of(lo[f].x, glo.x); i <= cell_of(hi[f].x, glo.x); ++i)
            for (int j = cell_of(lo[f].y, glo.y); j <= cell_of(hi[f].y, glo.y); ++j)
                for (int k = cell_of(lo[f].z, glo.z); k <= cell_of(hi[f].z, glo.z); ++k)
                    grid[key(i, j, k)].push_back(std::uint32_t(f));

    std::atomic<std::size_t> count{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nf, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
        std::vector<std::uint32_t> seen;
        std::size_t local = 0;
        for (std::size_t fa = r.begin(); fa != r.end(); ++fa) {
            seen.clear();
            for (int i = cell_of(lo[fa].x, glo.x); i <= cell_of(hi[fa].x, glo.x); ++i)
                for (int j = cell_of(lo[fa].y, glo.y); j <= cell_of(hi[fa].y, glo.y); ++j)
                    for (int k = cell_of(lo[fa].z, glo.z); k <= cell_of(hi[fa].z, glo.z); ++k) {
                        auto it = grid.find(key(i, j, k));
                        for (auto fb : it->second)
                            if (fb > fa) seen.push_back(fb);
                    }
            std::sort(seen.begin(), seen.end());
            seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
            const auto& ta = m.triangles[fa];
            const Vec3d A[3] = {Vec3d(m.positions[ta[0]]), Vec3d(m.positions[ta[1]]), Vec3d(m.positions[ta[2]])};
            for (auto fb : seen) {
                if (lo[fa].x > hi[fb].x || lo[fb].x > hi[fa].x || lo[fa].y > hi[fb].y || lo[fb].y > hi[fa].y ||
                    lo[fa].z > hi[fb].z || lo[fb].z > hi[fa].z)
                    continue;
                const auto& tb = m.triangles[fb];
                int shared = 0, sa = -1, sb = -1;
                for (int x = 0; x < 3; ++x)
                    for (int y = 0; y < 3; ++y)
                        if (ta[x] == tb[y]) { ++shared; sa = x; sb = y; }
                if (shared >= 2) continue;
                const Vec3d B[3] = {Vec3d(m.positions[tb[0]]), Vec3d(m.positions[tb[1]]), Vec3d(m.positions[tb[2]])};
                bool hit = false;
                for (int e = 0; e < 3 && !hit; ++e) {
                    // With a shared vertex, only the edges away from it can cross properly.
                    if (shared == 1 && (e == sa || (e + 1) % 3 == sa)) {} else
                        hit = segment_crosses(A[e], A[(e + 1) % 3], B[0], B[1], B[2]);
                    if (!hit && !(shared == 1 && (e == sb || (e + 1) % 3 == sb)))
                        hit = segment_crosses(B[e], B[(e + 1) % 3], A[0], A[1], A[2]);
                }
                local += hit;
            }
        }
        count += local;
    });
    return count.load();
}

} // namespace cm
