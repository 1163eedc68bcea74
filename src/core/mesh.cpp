#include "core/mesh.h"

#include <algorithm>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

namespace cm {

void Mesh::bounds_of(const std::vector<Vec3f>& positions, Vec3f& lo, Vec3f& hi) {
    if (positions.empty()) {
        lo = hi = Vec3f{};
        return;
    }
    // In parallel: min and max come out the same in any order.
    using Box = std::array<Vec3f, 2>;
    const Box b = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, positions.size(), 1 << 16), Box{positions[0], positions[0]},
        [&](const tbb::blocked_range<std::size_t>& r, Box x) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) x = {vmin(x[0], positions[i]), vmax(x[1], positions[i])};
            return x;
        },
        [](const Box& x, const Box& y) {
            return Box{vmin(x[0], y[0]), vmax(x[1], y[1])};
        });
    lo = b[0];
    hi = b[1];
}

void Mesh::compute_normals() {
    std::vector<Vec3d> acc(positions.size());
    for (const auto& t : triangles) {
        const Vec3d a(positions[t[0]]), b(positions[t[1]]), c(positions[t[2]]);
        const Vec3d n = cross(b - a, c - a); // length = 2 * area: area weighting
        for (int k = 0; k < 3; ++k) acc[t[k]] += n;
    }
    normals.resize(positions.size());
    for (std::size_t i = 0; i < acc.size(); ++i) normals[i] = Vec3f(normalize(acc[i]));
}

} // namespace cm
