#include "smooth_creases.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace cm {

namespace {

// Per vertex: the sharp edges met (to 3, "more than two") and the first two far ends.
struct Sharp {
    std::uint32_t count = 0;
    std::uint32_t ends[2] = {0, 0};
    void add(std::uint32_t w) {
        if (count < 2) ends[count] = w;
        count = std::min<std::uint32_t>(count + 1, 3);
    }
};

} // namespace

CreaseHold hold_creases(const Mesh& in, const VertexAdjacency& ring, double angle_deg) {
    const std::size_t nv = in.positions.size(), nf = in.triangles.size();
    std::vector<Vec3d> normal(nf);
    for (std::size_t f = 0; f < nf; ++f) {
        const auto& t = in.triangles[f];
        const Vec3d p0(in.positions[t[0]]);
        normal[f] = cross(Vec3d(in.positions[t[1]]) - p0, Vec3d(in.positions[t[2]]) - p0); // area-weighted
    }
    // Every edge of every face keyed by its two vertices; an edge with exactly two faces is
    // sharp when their normals are further apart than the angle.
    std::vector<std::pair<std::uint64_t, std::uint32_t>> edges;
    edges.reserve(3 * nf);
    for (std::size_t f = 0; f < nf; ++f)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = in.triangles[f][std::size_t(k)], b = in.triangles[f][std::size_t((k + 1) % 3)];
            edges.emplace_back(std::uint64_t(std::min(a, b)) << 32 | std::max(a, b), std::uint32_t(f));
        }
    std::sort(edges.begin(), edges.end());
    const double cos_angle = std::cos(angle_deg * 3.14159265358979323846 / 180.0);
    std::vector<Sharp> sharp(nv);
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i;
        while (j < edges.size() && edges[j].first == edges[i].first) ++j;
        if (j - i == 2) {
            const Vec3d &n0 = normal[edges[i].second], &n1 = normal[edges[i + 1].second];
            const double l0 = length(n0), l1 = length(n1);
            if (l0 > 0 && l1 > 0 && dot(n0, n1) < cos_angle * l0 * l1) {
                const auto a = std::uint32_t(edges[i].first >> 32), b = std::uint32_t(edges[i].first);
                sharp[a].add(b);
                sharp[b].add(a);
            }
        }
        i = j;
    }
    std::vector<Vec3d> mean(nv, Vec3d(0, 0, 0));
    for (std::size_t f = 0; f < nf; ++f)
        for (auto v : in.triangles[f]) mean[v] += normal[f];
    CreaseHold h;
    h.plane.assign(nv, Vec3f(0, 0, 0));
    h.adj.offsets.assign(nv + 1, 0);
    for (std::size_t v = 0; v < nv; ++v) {
        const auto u = std::uint32_t(v);
        if (sharp[v].count == 2) {
            ++h.crease_vertices;
            h.adj.neighbours.insert(h.adj.neighbours.end(), sharp[v].ends, sharp[v].ends + 2);
        } else if (sharp[v].count > 0) {
            ++h.held_vertices; // stays
        } else {
            h.adj.neighbours.insert(h.adj.neighbours.end(), ring.begin(u), ring.end(u));
            const bool beside =
                std::any_of(ring.begin(u), ring.end(u), [&](std::uint32_t w) { return sharp[w].count > 0; });
            if (beside && length(mean[v]) > 0) {
                h.plane[v] = Vec3f(normalize(mean[v]));
                ++h.plane_vertices;
            }
        }
        h.adj.offsets[v + 1] = std::uint32_t(h.adj.neighbours.size());
    }
    return h;
}

} // namespace cm
