#include "geometry/mesh_check.h"

#include <algorithm>
#include <atomic>
#include <memory>
#include <unordered_map>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include "geometry/disjoint_sets.h"

namespace cm {

namespace {

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
    DisjointSets local(k);
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

bool repeated(const std::array<std::uint32_t, 3>& t) { return t[0] == t[1] || t[1] == t[2] || t[0] == t[2]; }

// A union-find that threads share: roots linked by compare-and-swap, always the larger index
// under the smaller, so the forest stays one; paths halved on the way.
struct SharedForest {
    std::uint32_t* parent;
    std::uint32_t find(std::uint32_t x) const {
        for (;;) {
            std::uint32_t p = std::atomic_ref<std::uint32_t>(parent[x]).load(std::memory_order_relaxed);
            if (p == x) return x;
            const std::uint32_t g = std::atomic_ref<std::uint32_t>(parent[p]).load(std::memory_order_relaxed);
            if (g != p)
                std::atomic_ref<std::uint32_t>(parent[x]).compare_exchange_weak(p, g, std::memory_order_relaxed);
            x = g;
        }
    }
    void unite(std::uint32_t a, std::uint32_t b) const {
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
    }
};

struct EdgeCounts {
    std::size_t edges = 0, boundary = 0, nonmanifold = 0, inconsistent = 0;
};

// The check in named steps. Undirected edges bucketed by their lower vertex (a counting sort:
// each bucket holds the few edges of one vertex), and the faces around each vertex, both as
// offset arrays: no sort of all edges, no allocation per vertex. The faces go in a few chunks
// side by side, each counting its corners and edges per vertex in arrays of its own and then
// writing them from its own place in each bucket (the buckets hold what one pass in face order
// would put there, in that order). The large arrays are left unset by their constructors and
// written first side by side (a zero fill would map all their pages on one thread).
class MeshChecker {
public:
    explicit MeshChecker(const Mesh& m)
        : m_(m),
          nv_(m.positions.size()),
          nf_(m.triangles.size()),
          chunks_(nf_ < (std::size_t(1) << 16)
                      ? 1
                      : std::min<std::size_t>(8, std::max(1, tbb::this_task_arena::max_concurrency()))),
          per_((nf_ + chunks_ - 1) / chunks_),
          fat_(chunks_),
          eat_(chunks_) {}

    MeshCheck run() {
        count_per_chunk();
        place_chunks();
        fill_buckets();
        MeshCheck r;
        count_components(r);
        sum_faces(r);
        const EdgeCounts ec = count_edges();
        r.boundary_edges = ec.boundary;
        r.nonmanifold_edges = ec.nonmanifold;
        r.inconsistent_edges = ec.inconsistent;
        r.nonmanifold_vertices = count_split_fans();
        r.euler = r.euler - long(ec.edges) + long(nf_ - r.degenerate_faces);
        return r;
    }

private:
    // Each chunk's corners and edges per vertex.
    void count_per_chunk() {
        tbb::parallel_for(std::size_t(0), chunks_, [&](std::size_t c) {
            fat_[c].assign(nv_, 0);
            eat_[c].assign(nv_, 0);
            for (std::size_t f = c * per_, e = std::min(nf_, f + per_); f < e; ++f) {
                const auto& t = m_.triangles[f];
                for (int k = 0; k < 3; ++k) ++fat_[c][t[k]];
                if (repeated(t)) continue;
                for (int k = 0; k < 3; ++k) ++eat_[c][std::min(t[k], t[(k + 1) % 3])];
            }
        });
    }

    // The buckets' offsets, and each chunk's counts turned into its place in each bucket.
    void place_chunks() {
        // (std::make_unique_for_overwrite: trivial elements left unset)
        eoff_ = std::make_unique_for_overwrite<std::size_t[]>(nv_ + 1);
        foff_ = std::make_unique_for_overwrite<std::size_t[]>(nv_ + 1);
        eoff_[0] = foff_[0] = 0;
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv_, 1 << 14), [&](const auto& range) {
            for (std::size_t v = range.begin(); v != range.end(); ++v) {
                std::size_t ne = 0, nfc = 0;
                for (std::size_t c = 0; c < chunks_; ++c) {
                    ne += eat_[c][v];
                    nfc += fat_[c][v];
                }
                eoff_[v + 1] = ne;
                foff_[v + 1] = nfc;
            }
        });
        for (std::size_t v = 0; v < nv_; ++v) {
            eoff_[v + 1] += eoff_[v];
            foff_[v + 1] += foff_[v];
        }
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv_, 1 << 14), [&](const auto& range) {
            for (std::size_t v = range.begin(); v != range.end(); ++v) {
                std::size_t e = eoff_[v], f = foff_[v];
                for (std::size_t c = 0; c < chunks_; ++c) {
                    const std::uint32_t ne = eat_[c][v], nfc = fat_[c][v];
                    eat_[c][v] = std::uint32_t(e - eoff_[v]);
                    fat_[c][v] = std::uint32_t(f - foff_[v]);
                    e += ne;
                    f += nfc;
                }
            }
        });
    }

    // The edges and the faces around each vertex written into their buckets, the vertices
    // that have an edge marked, and the components joined through the faces.
    void fill_buckets() {
        // (higher vertex << 1) | forward, per bucket; each entry of both written once
        edges_ = std::make_unique_for_overwrite<std::uint64_t[]>(eoff_[nv_]);
        vfaces_ = std::make_unique_for_overwrite<std::uint32_t[]>(foff_[nv_]);
        parent_ = std::make_unique_for_overwrite<std::uint32_t[]>(nv_);
        used_ = std::make_unique_for_overwrite<char[]>(nv_);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv_, 1 << 14), [&](const auto& range) {
            for (std::size_t v = range.begin(); v != range.end(); ++v) {
                parent_[v] = std::uint32_t(v);
                used_[v] = 0;
            }
        });
        const SharedForest forest{parent_.get()};
        tbb::parallel_for(std::size_t(0), chunks_, [&](std::size_t c) {
            std::uint32_t *fc = fat_[c].data(), *ec = eat_[c].data();
            for (std::size_t f = c * per_, e = std::min(nf_, f + per_); f < e; ++f) {
                const auto& t = m_.triangles[f];
                for (int k = 0; k < 3; ++k) vfaces_[foff_[t[k]] + fc[t[k]]++] = std::uint32_t(f);
                if (repeated(t)) continue;
                for (int k = 0; k < 3; ++k) {
                    const std::uint32_t u = t[k], v = t[(k + 1) % 3], lo = std::min(u, v);
                    std::atomic_ref<char>(used_[u]).store(1, std::memory_order_relaxed);
                    edges_[eoff_[lo] + ec[lo]++] = (std::uint64_t(std::max(u, v)) << 1) | std::uint64_t(u < v);
                }
                forest.unite(t[0], t[1]);
                forest.unite(t[1], t[2]);
            }
        });
        fat_.clear();
        eat_.clear();
    }

    // Components (roots among the vertices with an edge), and those vertices for the Euler
    // characteristic.
    void count_components(MeshCheck& r) const {
        struct Counts {
            std::size_t used = 0, roots = 0;
        };
        const Counts vc = tbb::parallel_reduce(
            tbb::blocked_range<std::size_t>(0, nv_, 1 << 14), Counts{},
            [&](const tbb::blocked_range<std::size_t>& range, Counts c) {
                for (std::size_t v = range.begin(); v != range.end(); ++v)
                    if (used_[v]) {
                        ++c.used;
                        c.roots += parent_[v] == v;
                    }
                return c;
            },
            [](Counts x, const Counts& y) {
                return Counts{x.used + y.used, x.roots + y.roots};
            });
        r.components = vc.roots;
        r.euler = long(vc.used);
    }

    // Area, volume and degenerate faces, summed in one order whatever the thread count.
    void sum_faces(MeshCheck& r) const {
        struct Sums {
            double area = 0, volume = 0;
            std::size_t degenerate = 0;
        };
        const Sums sums = tbb::parallel_deterministic_reduce(
            tbb::blocked_range<std::size_t>(0, nf_, 1 << 14), Sums{},
            [&](const tbb::blocked_range<std::size_t>& range, Sums acc) {
                for (std::size_t f = range.begin(); f != range.end(); ++f) {
                    const auto& t = m_.triangles[f];
                    if (repeated(t)) {
                        ++acc.degenerate;
                        continue;
                    }
                    const Vec3d a(m_.positions[t[0]]), b(m_.positions[t[1]]), c(m_.positions[t[2]]);
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
    }

    // Each bucket sorted, and its edges counted by how many faces use them and which way.
    EdgeCounts count_edges() {
        return tbb::parallel_reduce(
            tbb::blocked_range<std::size_t>(0, nv_, 4096), EdgeCounts{},
            [&](const tbb::blocked_range<std::size_t>& range, EdgeCounts c) {
                for (std::size_t v = range.begin(); v != range.end(); ++v) {
                    std::uint64_t* b = edges_.get() + eoff_[v];
                    std::uint64_t* e = edges_.get() + eoff_[v + 1];
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
    }

    // Vertices whose faces form more than one fan.
    std::size_t count_split_fans() const {
        return tbb::parallel_reduce(
            tbb::blocked_range<std::size_t>(0, nv_, 4096), std::size_t(0),
            [&](const tbb::blocked_range<std::size_t>& range, std::size_t c) {
                for (std::size_t v = range.begin(); v != range.end(); ++v) {
                    const std::size_t k = foff_[v + 1] - foff_[v];
                    if (k >= 2 && !one_fan(m_, std::uint32_t(v), vfaces_.get() + foff_[v], k)) ++c;
                }
                return c;
            },
            [](std::size_t x, std::size_t y) { return x + y; });
    }

    const Mesh& m_;
    const std::size_t nv_, nf_;
    const std::size_t chunks_, per_;                    ///< chunks of faces, and faces per chunk
    std::vector<std::vector<std::uint32_t>> fat_, eat_; ///< per chunk: counts, then cursors
    std::unique_ptr<std::size_t[]> eoff_, foff_;        ///< per vertex: its bucket of edges, of faces
    std::unique_ptr<std::uint64_t[]> edges_;
    std::unique_ptr<std::uint32_t[]> vfaces_;
    std::unique_ptr<std::uint32_t[]> parent_; ///< the components' forest
    std::unique_ptr<char[]> used_;            ///< the vertex starts an edge
};

} // namespace

MeshCheck check_mesh(const Mesh& m) { return MeshChecker(m).run(); }

} // namespace cm
