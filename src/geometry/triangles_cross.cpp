// The triangle test of mesh_intersect.h: whether two triangles of a mesh cross at a point
// inside both.
#include <cmath>
#include <cstdint>
#include <vector>

#include "geometry/mesh_intersect.h"

namespace cm {

namespace {

// Does the segment [p, q] cross triangle (a, b, c) at a point strictly inside both?
bool segment_crosses(const Vec3d& p, const Vec3d& q, const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    const Vec3d d = q - p, e1 = b - a, e2 = c - a;
    const Vec3d h = cross(d, e2);
    const double det = dot(e1, h);
    const double scale = length(d) * length(e1) * length(e2);
    if (std::fabs(det) <= 1e-12 * scale) return false; // parallel or coplanar
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

bool triangles_cross(const std::vector<Vec3f>& p, const std::array<std::uint32_t, 3>& ta,
                     const std::array<std::uint32_t, 3>& tb) {
    int shared = 0, sa = -1, sb = -1;
    for (int x = 0; x < 3; ++x)
        for (int y = 0; y < 3; ++y)
            if (ta[x] == tb[y]) {
                ++shared;
                sa = x;
                sb = y;
            }
    if (shared >= 2) return false;
    const Vec3d A[3] = {Vec3d(p[ta[0]]), Vec3d(p[ta[1]]), Vec3d(p[ta[2]])};
    const Vec3d B[3] = {Vec3d(p[tb[0]]), Vec3d(p[tb[1]]), Vec3d(p[tb[2]])};
    // Early out: the other triangle's (unshared) corners all strictly on one side of a plane.
    auto one_side = [](const Vec3d(&T)[3], const Vec3d(&U)[3], int skip) {
        const Vec3d n = cross(T[1] - T[0], T[2] - T[0]);
        bool pos = false, neg = false;
        for (int i = 0; i < 3; ++i) {
            if (i == skip) continue;
            const double d = dot(n, U[i] - T[0]);
            pos |= d >= 0;
            neg |= d <= 0;
        }
        return !(pos && neg);
    };
    if (one_side(A, B, sb) || one_side(B, A, sa)) return false;
    for (int e = 0; e < 3; ++e) {
        // With a shared vertex, only the edges away from it can cross properly.
        if (!(shared == 1 && (e == sa || (e + 1) % 3 == sa)) && segment_crosses(A[e], A[(e + 1) % 3], B[0], B[1], B[2]))
            return true;
        if (!(shared == 1 && (e == sb || (e + 1) % 3 == sb)) && segment_crosses(B[e], B[(e + 1) % 3], A[0], A[1], A[2]))
            return true;
    }
    return false;
}

} // namespace cm
