#include "core/mesh.h"

#include <algorithm>
#include <numeric>
#include <unordered_map>

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

MeshCheck check_mesh(const Mesh& m) {
    MeshCheck r;
    const std::size_t nv = m.positions.size();
    // Directed edges, sorted, to count uses per undirected edge and per direction.
    std::vector<std::pair<std::uint64_t, bool>> edges; // key(min,max), forward?
    edges.reserve(m.triangles.size() * 3);
    Dsu dsu(nv);
    std::vector<char> used(nv, 0);
    for (const auto& t : m.triangles) {
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
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
            std::uint32_t u = t[k], v = t[(k + 1) % 3];
            used[u] = 1;
            dsu.unite(u, v);
            const bool fwd = u < v;
            const std::uint64_t key = (std::uint64_t(std::min(u, v)) << 32) | std::max(u, v);
            edges.emplace_back(key, fwd);
        }
    }
    std::sort(edges.begin(), edges.end());
    std::size_t ne = 0;
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i, fwd = 0;
        while (j < edges.size() && edges[j].first == edges[i].first) {
            fwd += edges[j].second;
            ++j;
        }
        const std::size_t n = j - i;
        ++ne;
        if (n == 1) ++r.boundary_edges;
        else if (n > 2) ++r.nonmanifold_edges;
        else if (fwd != 1) ++r.inconsistent_edges;
        i = j;
    }
    // Vertex manifoldness: the faces around each vertex form one fan (connected via shared edges).
    std::vector<std::vector<std::uint32_t>> vf(nv);
    for (std::uint32_t f = 0; f < m.triangles.size(); ++f)
        for (int k = 0; k < 3; ++k) vf[m.triangles[f][k]].push_back(f);
    for (std::uint32_t v = 0; v < nv; ++v) {
        const auto& fs = vf[v];
        if (fs.size() < 2) continue;
        // Union faces sharing an edge through v.
        std::unordered_map<std::uint32_t, std::uint32_t> other_to_face;
        Dsu local(fs.size());
        for (std::uint32_t i = 0; i < fs.size(); ++i) {
            const auto& t = m.triangles[fs[i]];
            for (int k = 0; k < 3; ++k) {
                if (t[k] == v) continue;
                auto [it, fresh] = other_to_face.emplace(t[k], i);
                if (!fresh) local.unite(i, it->second);
            }
        }
        std::uint32_t root = local.find(0);
        for (std::uint32_t i = 1; i < fs.size(); ++i)
            if (local.find(i) != root) {
                ++r.nonmanifold_vertices;
                break;
            }
    }
    std::size_t nused = 0;
    for (std::uint32_t v = 0; v < nv; ++v) {
        if (!used[v]) continue;
        ++nused;
        if (dsu.find(v) == v) ++r.components;
    }
    r.euler = long(nused) - long(ne) + long(m.triangles.size() - r.degenerate_faces);
    return r;
}

} // namespace cm
