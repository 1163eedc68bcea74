#include "geometry/mesh_check.h"

#include <algorithm>
#include <atomic>
#include <memory>
#include <numeric>
#include <unordered_map>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

namespace cm {

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
    // sort of all edges, no allocation per vertex. The faces go in a few chunks side by side,
    // each counting its corners and edges per vertex in arrays of its own and then writing
    // them from its own place in each bucket (the buckets hold what one pass in face order
    // would put there, in that order).
    auto repeated = [](const std::array<std::uint32_t, 3>& t) { return t[0] == t[1] || t[1] == t[2] || t[0] == t[2]; };
    const std::size_t chunks = nf < (std::size_t(1) << 16)
                                   ? 1
                                   : std::min<std::size_t>(8, std::max(1, tbb::this_task_arena::max_concurrency()));
    const std::size_t per = (nf + chunks - 1) / chunks;
    std::vector<std::vector<std::uint32_t>> fat(chunks), eat(chunks); // per chunk: counts, then cursors
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
        fat[c].assign(nv, 0);
        eat[c].assign(nv, 0);
        for (std::size_t f = c * per, e = std::min(nf, f + per); f < e; ++f) {
            const auto& t = m.triangles[f];
            for (int k = 0; k < 3; ++k) ++fat[c][t[k]];
            if (repeated(t)) continue;
            for (int k = 0; k < 3; ++k) ++eat[c][std::min(t[k], t[(k + 1) % 3])];
        }
    });
    // The large arrays below are left unset by their constructors and written first side by
    // side (a zero fill would map all their pages on one thread).
    // (std::make_unique_for_overwrite: trivial elements left unset)
    const auto eoff = std::make_unique_for_overwrite<std::size_t[]>(nv + 1);
    const auto foff = std::make_unique_for_overwrite<std::size_t[]>(nv + 1);
    eoff[0] = foff[0] = 0;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 1 << 14), [&](const auto& range) {
        for (std::size_t v = range.begin(); v != range.end(); ++v) {
            std::size_t ne = 0, nfc = 0;
            for (std::size_t c = 0; c < chunks; ++c) {
                ne += eat[c][v];
                nfc += fat[c][v];
            }
            eoff[v + 1] = ne;
            foff[v + 1] = nfc;
        }
    });
    for (std::size_t v = 0; v < nv; ++v) {
        eoff[v + 1] += eoff[v];
        foff[v + 1] += foff[v];
    }
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 1 << 14), [&](const auto& range) {
        for (std::size_t v = range.begin(); v != range.end(); ++v) {
            std::size_t e = eoff[v], f = foff[v];
            for (std::size_t c = 0; c < chunks; ++c) {
                const std::uint32_t ne = eat[c][v], nfc = fat[c][v];
                eat[c][v] = std::uint32_t(e - eoff[v]);
                fat[c][v] = std::uint32_t(f - foff[v]);
                e += ne;
                f += nfc;
            }
        }
    });
    // (higher vertex << 1) | forward, per bucket; each entry of both written once
    const auto edges = std::make_unique_for_overwrite<std::uint64_t[]>(eoff[nv]);
    const auto vfaces = std::make_unique_for_overwrite<std::uint32_t[]>(foff[nv]);
    // Components: a union-find the chunks share (roots linked by compare-and-swap, always
    // the larger index under the smaller, so the forest stays one; paths halved on the way).
    const auto parent = std::make_unique_for_overwrite<std::uint32_t[]>(nv);
    const auto used = std::make_unique_for_overwrite<char[]>(nv);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 1 << 14), [&](const auto& range) {
        for (std::size_t v = range.begin(); v != range.end(); ++v) {
            parent[v] = std::uint32_t(v);
            used[v] = 0;
        }
    });
    auto find = [&](std::uint32_t x) {
        for (;;) {
            std::uint32_t p = std::atomic_ref<std::uint32_t>(parent[x]).load(std::memory_order_relaxed);
            if (p == x) return x;
            const std::uint32_t g = std::atomic_ref<std::uint32_t>(parent[p]).load(std::memory_order_relaxed);
            if (g != p)
                std::atomic_ref<std::uint32_t>(parent[x]).compare_exchange_weak(p, g, std::memory_order_relaxed);
            x = g;
        }
    };
    auto unite = [&](std::uint32_t a, std::uint32_t b) {
        for (;;) {
            a = find(a);
            b = find(b);
            if (a == b) return;
            if (a < b) std::swap(a, b);
            std::uint32_t expected = a;
            if (std::atomic_ref<std::uint32_t>(parent[a]).compare_exchange_strong(expected, b,
                                                                                  std::memory_order_relaxed))
                return;
        }
    };
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
        std::uint32_t *fc = fat[c].data(), *ec = eat[c].data();
        for (std::size_t f = c * per, e = std::min(nf, f + per); f < e; ++f) {
            const auto& t = m.triangles[f];
            for (int k = 0; k < 3; ++k) vfaces[foff[t[k]] + fc[t[k]]++] = std::uint32_t(f);
            if (repeated(t)) continue;
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t u = t[k], v = t[(k + 1) % 3], lo = std::min(u, v);
                std::atomic_ref<char>(used[u]).store(1, std::memory_order_relaxed);
                edges[eoff[lo] + ec[lo]++] = (std::uint64_t(std::max(u, v)) << 1) | std::uint64_t(u < v);
            }
            unite(t[0], t[1]);
            unite(t[1], t[2]);
        }
    });
    fat.clear();
    eat.clear();
    struct Counts {
        std::size_t used = 0, roots = 0;
    };
    const Counts vc = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, nv, 1 << 14), Counts{},
        [&](const tbb::blocked_range<std::size_t>& range, Counts c) {
            for (std::size_t v = range.begin(); v != range.end(); ++v)
                if (used[v]) {
                    ++c.used;
                    c.roots += parent[v] == v;
                }
            return c;
        },
        [](Counts x, const Counts& y) {
            return Counts{x.used + y.used, x.roots + y.roots};
        });
    r.components = vc.roots;
    r.euler = long(vc.used);
    // Area, volume and degenerate faces, summed in one order whatever the thread count.
    struct Sums {
        double area = 0, volume = 0;
        std::size_t degenerate = 0;
    };
    const Sums sums = tbb::parallel_deterministic_reduce(
        tbb::blocked_range<std::size_t>(0, nf, 1 << 14), Sums{},
        [&](const tbb::blocked_range<std::size_t>& range, Sums acc) {
            for (std::size_t f = range.begin(); f != range.end(); ++f) {
                const auto& t = m.triangles[f];
                if (repeated(t)) {
                    ++acc.degenerate;
                    continue;
                }
                const Vec3d a(m.positions[t[0]]), b(m.positions[t[1]]), c(m.positions[t[2]]);
                const double area2 = length(cross(b - a, c - a));
                if (area2 == 0.0) ++acc.degenerate;
                acc.area += 0.5 * area2;
                acc.volume += dot(a, cross(b, c)) / 6.0;
            }
            return acc;
        },
        [](Sums x, const Sums& y) {
            return Sums{x.area + y.area, x.volume + y.volume, x.degenerate + y.degenerate};
        });
    r.area = sums.area;
    r.signed_volume = sums.volume;
    r.degenerate_faces = sums.degenerate;
    const EdgeCounts ec = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, nv, 4096), EdgeCounts{},
        [&](const tbb::blocked_range<std::size_t>& range, EdgeCounts c) {
            for (std::size_t v = range.begin(); v != range.end(); ++v) {
                std::uint64_t* b = edges.get() + eoff[v];
                std::uint64_t* e = edges.get() + eoff[v + 1];
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
                if (k >= 2 && !one_fan(m, std::uint32_t(v), vfaces.get() + foff[v], k)) ++c;
            }
            return c;
        },
        [](std::size_t x, std::size_t y) { return x + y; });
    r.euler = r.euler - long(ec.edges) + long(nf - r.degenerate_faces);
    return r;
}

} // namespace cm
