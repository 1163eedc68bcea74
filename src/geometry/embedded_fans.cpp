// The embedded-fan test of mesh_intersect.h (embedded_fans): the vertices whose faces lie
// over a plane one-to-one, whose pairs of faces a crossing test may leave out.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "geometry/mesh_intersect.h"

namespace cm {

std::vector<char> embedded_fans(const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                const std::vector<Vec3f>& p) {
    const std::size_t nv = p.size(), nf = triangles.size();
    std::vector<char> embedded(nv, 0);
    // Sums per vertex over its faces, with no lists of faces: each task owns a range of the
    // vertices and goes through every face, adding what the faces' corners in its range give
    // (no two tasks write one vertex). Any axis would do for the test below as long as every
    // face is judged against the same one; the sum of the face normals is the natural one,
    // and float is enough for it.
    std::vector<Vec3f> axis(nv, Vec3f(0, 0, 0));
    std::vector<std::uint64_t> balance(nv, 0); // each neighbour as often before v as after it: closed cycles
    std::vector<float> turn(nv, 0.0f);
    std::vector<std::uint8_t> count(nv, 0); // faces, up to 255
    const std::size_t tasks =
        nf < (std::size_t(1) << 16) ? 1 : std::size_t(std::max(1, tbb::this_task_arena::max_concurrency()));
    const std::size_t per = (nv + tasks - 1) / tasks;
    auto mix = [](std::uint64_t y) { return (y + 1) * 0x9E3779B97F4A7C15ull ^ (y >> 7) * 0xC2B2AE3D27D4EB4Full; };
    std::atomic<bool> bad_index{false}; // a face names a vertex that does not exist
    // face(t, corners, P, n): the face's corners in the task's range (bit c: corner c), its
    // corners' positions and its normal (the cross product of its sides from any corner).
    auto over_faces = [&](auto&& face) {
        tbb::parallel_for(std::size_t(0), tasks, [&](std::size_t k) {
            const std::uint32_t lo = std::uint32_t(k * per), hi = std::uint32_t(std::min(nv, (k + 1) * per));
            for (std::size_t f = 0; f < nf; ++f) {
                const auto& t = triangles[f];
                if (t[0] >= nv || t[1] >= nv || t[2] >= nv) {
                    bad_index.store(true, std::memory_order_relaxed);
                    continue;
                }
                const unsigned mine = unsigned(t[0] >= lo && t[0] < hi) | unsigned(t[1] >= lo && t[1] < hi) << 1 |
                                      unsigned(t[2] >= lo && t[2] < hi) << 2;
                if (!mine) continue;
                const Vec3d P[3] = {Vec3d(p[t[0]]), Vec3d(p[t[1]]), Vec3d(p[t[2]])};
                face(t, mine, P, cross(P[1] - P[0], P[2] - P[0]));
            }
        });
    };
    over_faces([&](const std::array<std::uint32_t, 3>& t, unsigned mine, const Vec3d(&)[3], const Vec3d& n) {
        const bool degenerate = t[0] == t[1] || t[1] == t[2] || t[2] == t[0];
        for (int c = 0; c < 3; ++c) {
            if (!((mine >> c) & 1u)) continue;
            const std::uint32_t v = t[std::size_t(c)];
            axis[v] += Vec3f(n);
            balance[v] += mix(t[std::size_t((c + 1) % 3)]) - mix(t[std::size_t((c + 2) % 3)]);
            count[v] = degenerate ? 255 : std::uint8_t(std::min(255, count[v] + 1));
        }
    });
    if (bad_index) return embedded; // a fan could miss a face: none is vouched for
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 1 << 14), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t v = r.begin(); v != r.end(); ++v) {
            const Vec3d n(axis[v]);
            const double len = length(n);
            if (count[v] < 3 || count[v] > 64 || balance[v] != 0 || !(len > 0) || !std::isfinite(len)) {
                turn[v] = HUGE_VALF; // not vouched for
                continue;
            }
            axis[v] = Vec3f(n * (1.0 / len));
        }
    });
    // Each face's angle at v seen along the axis is theta, with sin and cos from the projected
    // sides; (pi/2)(1 - cos) + sin bounds it from above on [0, pi] (no arc function per face).
    // One cycle winding once adds up to 2 pi; any more, to 4 pi.
    constexpr double kHalfPi = 1.57079632679489661923;
    over_faces([&](const std::array<std::uint32_t, 3>& t, unsigned mine, const Vec3d(&P)[3], const Vec3d& n) {
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t v = t[std::size_t(c)];
            if (!((mine >> c) & 1u) || turn[v] == HUGE_VALF) continue;
            const Vec3d ax(axis[v]);
            const Vec3d u = P[(c + 1) % 3] - P[c], w = P[(c + 2) % 3] - P[c];
            const double sine = dot(n, ax); // the projected sides' cross product
            // Turning the fan's way, by a margin.
            if (!(sine > 0 && sine * sine > 1e-18 * dot(n, n))) {
                turn[v] = HUGE_VALF;
                continue;
            }
            const double cosine = dot(u, w) - dot(u, ax) * dot(w, ax); // of the projected sides
            const double r = std::sqrt(sine * sine + cosine * cosine);
            turn[v] += float(kHalfPi * (1 - cosine / r) + sine / r);
        }
    });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 1 << 14), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t v = r.begin(); v != r.end(); ++v) embedded[v] = turn[v] < float(8 * kHalfPi - 1e-2);
    });
    return embedded;
}

} // namespace cm
