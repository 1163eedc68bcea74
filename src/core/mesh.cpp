#include "core/mesh.h"

#include <algorithm>
#include <numeric>
#include <unordered_map>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

namespace cm {

void Mesh::bounds(Vec3f& lo, Vec3f& hi) const {
    if (positions.empty()) {
        lo = hi = Vec3f{};
        return;
    }
    lo = hi = positions[0];
    for (const auto& p : positions) {
        lo = vmin(lo, p);
        hi = vmax(hi, p);
    }
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

namespace {
struct Dsu {
    std::vector<std::uint32_t> p;
    explicit Dsu(std::size_t n) : p(n) { std::iota(p.begin(), p.end(), 0u); }
    std::uint32_t find(std::uint32_t x) {
        while (p[x] != x) {
            p[x] = p[p[x]];
            x = p[x];
        }
        return x;
    }
    void unite(std::uint32_t a, std::uint32_t b) { p[find(a)] = find(b); }
};
} // namespace

namespace {

struct EdgeCounts {
    std::size_t edges = 0, boundary = 0, nonmanifold = 0, inconsistent = 0;
};

// Whether the faces around vertex v form one fan (connected through edges at v): faces
// are joined when they share a vertex other than v. A fan of a few faces is checked pair
// by pair on the stack; a large one (a broken input) through a map of the other vertices.
bool one_fan(const Mesh& m, std::uint32_t v, const std::uint32_t* fs, std::size_t k) {
    constexpr std::size_t kSmall = 32;
    if (k <= kSmall) {
        std::uint32_t parent[kSmall] = {};
        for (std::uint32_t i = 0; i < k; ++i) parent[i] = i;
        auto find = [&](std::uint32_t x) {
            while (parent[x] != x) x = parent[x] = parent[parent[x]];
            return x;
        };
        for (std::uint32_t i = 0; i < k; ++i) {
            const auto& a = m.triangles[fs[i]];
            for (std::uint32_t j = i + 1; j < k; ++j) {
                const auto& b = m.triangles[fs[j]];
                bool shared = false;
                for (int x = 0; x < 3 && !shared; ++x)
                    if (a[x] != v) shared = a[x] == b[0] || a[x] == b[1] || a[x] == b[2];
                if (shared) parent[find(i)] = find(j);
            }
        }
        const std::uint32_t root = find(0);
        for (std::uint32_t i = 1; i < k; ++i)
            if (find(i) != root) return false;
        return true;
    }
    std::unordered_map<std::uint32_t, std::uint32_t> other_to_face;
    Dsu local(k);
    for (std::uint32_t i = 0; i < k; ++i) {
        const auto& t = m.triangles[fs[i]];
        for (int x = 0; x < 3; ++x) {
            if (t[x] == v) continue;
            auto [it, fresh] = other_to_face.emplace(t[x], i);
            if (!fresh) local.unite(i, it->second);
        }
    }
    const std::uint32_t root = local.find(0);
    for (std::uint32_t i = 1; i < k; ++i)
        if (local.find(i) != root) return false;
    return true;
}

} // namespace

MeshCheck check_mesh(const Mesh& m) {
    MeshCheck r;
    const std::size_t nv = m.positions.size(), nf = m.triangles.size();
    // Undirected edges bucketed by their lower vertex (a counting sort: each bucket holds the
    // few edges of one vertex), and the faces around each vertex, both as offset arrays: no
    // sort of all edges, no allocation per vertex.
    std::vector<std::size_t> eoff(nv + 1, 0), foff(nv + 1, 0);
    auto repeated = [](const std::array<std::uint32_t, 3>& t) { return t[0] == t[1] || t[1] == t[2] || t[0] == t[2]; };
    for (const auto& t : m.triangles) {
        for (int k = 0; k < 3; ++k) ++foff[std::size_t(t[k]) + 1];
        if (repeated(t)) continue;
        for (int k = 0; k < 3; ++k) ++eoff[std::size_t(std::min(t[k], t[(k + 1) % 3])) + 1];
    }
    for (std::size_t v = 0; v < nv; ++v) {
        eoff[v + 1] += eoff[v];
        foff[v + 1] += foff[v];
    }
    std::vector<std::uint64_t> edges(eoff[nv]); // (higher vertex << 1) | forward, per bucket
    std::vector<std::uint32_t> vfaces(foff[nv]);
    {
        std::vector<std::size_t> efill(eoff.begin(), eoff.end() - 1), ffill(foff.begin(), foff.end() - 1);
        Dsu dsu(nv);
        std::vector<char> used(nv, 0);
        for (std::size_t f = 0; f < nf; ++f) {
            const auto& t = m.triangles[f];
            for (int k = 0; k < 3; ++k) vfaces[ffill[t[k]]++] = std::uint32_t(f);
            if (repeated(t)) {
                ++r.degenerate_faces;
                continue;
            }
            const Vec3d a(m.positions[t[0]]), b(m.positions[t[1]]), c(m.positions[t[2]]);
            const Vec3d n = cross(b - a, c - a);
            const double area2 = length(n);
            if (area2 == 0.0) ++r.degenerate_faces;
            r.area += 0.5 * area2;
            r.signed_volume += dot(a, cross(b, c)) / 6.0;
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t u = t[k], v = t[(k + 1) % 3];
                used[u] = 1;
                dsu.unite(u, v);
                edges[efill[std::min(u, v)]++] = (std::uint64_t(std::max(u, v)) << 1) | std::uint64_t(u < v);
            }
        }
        std::size_t nused = 0;
        for (std::uint32_t v = 0; v < nv; ++v) {
            if (!used[v]) continue;
            ++nused;
            if (dsu.find(v) == v) ++r.components;
        }
        r.euler = long(nused);
    }
    const EdgeCounts ec = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, nv, 4096), EdgeCounts{},
        [&](const tbb::blocked_range<std::size_t>& range, EdgeCounts c) {
            for (std::size_t v = range.begin(); v != range.end(); ++v) {
                std::uint64_t* b = edges.data() + eoff[v];
                std::uint64_t* e = edges.data() + eoff[v + 1];
                std::sort(b, e);
                for (std::uint64_t* i = b; i != e;) {
                    std::uint64_t* j = i;
                    std::size_t fwd = 0;
                    while (j != e && (*j >> 1) == (*i >> 1)) fwd += *j++ & 1;
                    const std::size_t n = std::size_t(j - i);
                    ++c.edges;
                    if (n == 1) ++c.boundary;
                    else if (n > 2) ++c.nonmanifold;
                    else if (fwd != 1) ++c.inconsistent;
                    i = j;
                }
            }
            return c;
        },
        [](EdgeCounts x, const EdgeCounts& y) {
            x.edges += y.edges;
            x.boundary += y.boundary;
            x.nonmanifold += y.nonmanifold;
            x.inconsistent += y.inconsistent;
            return x;
        });
    r.boundary_edges = ec.boundary;
    r.nonmanifold_edges = ec.nonmanifold;
    r.inconsistent_edges = ec.inconsistent;
    r.nonmanifold_vertices = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, nv, 4096), std::size_t(0),
        [&](const tbb::blocked_range<std::size_t>& range, std::size_t c) {
            for (std::size_t v = range.begin(); v != range.end(); ++v) {
                const std::size_t k = foff[v + 1] - foff[v];
                if (k >= 2 && !one_fan(m, std::uint32_t(v), vfaces.data() + foff[v], k)) ++c;
            }
            return c;
        },
        [](std::size_t x, std::size_t y) { return x + y; });
    r.euler = r.euler - long(ec.edges) + long(nf - r.degenerate_faces);
    return r;
}

} // namespace cm
