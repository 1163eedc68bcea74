// The collapse engine and the vertex queue of the polygon reduction (mesh_decimate_internal.h).
#include "mesh_decimate_internal.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace cm::decimate {

namespace {

/// sqrt(3) L_max^2 / (4 A): 1 for an equilateral triangle, large for slivers.
double aspect_ratio(const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    const double l = std::max({dot(b - a, b - a), dot(c - b, c - b), dot(a - c, a - c)});
    const double area2 = length(cross_of(a, b, c)); // twice the area
    return area2 > 0 ? std::sqrt(3.0) * l / (2.0 * area2) : HUGE_VAL;
}

} // namespace

Collapser::Collapser(Mesh& m, const std::vector<char>* frozen, const std::vector<char>* locks)
    : mesh_(m), P_(m.positions), T_(m.triangles) {
    const std::size_t nv = P_.size(), nf = T_.size();
    vdead_.assign(nv, 0);
    alive_faces_ = nf;
    build_lists();
    normals_.resize(nf);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nf, 4096), [&](const auto& r) {
        for (std::size_t f = r.begin(); f != r.end(); ++f) normals_[f] = face_normal(std::uint32_t(f));
    });
    if (locks && locks->size() == nv) {
        lock_ = *locks;
        // locked() counts the vertices locked by their fan: a frozen one is asked (few are).
        for (std::size_t v = 0; v < nv; ++v)
            locked_ += lock_[v] && vcount_[v] > 0 && (!(frozen && (*frozen)[v]) || !closed_fan(std::uint32_t(v)));
        return;
    }
    // Lock every vertex whose faces do not form one consistently oriented closed fan
    // (boundary, non-manifold edge or vertex, flipped neighbour, huge valence).
    lock_.assign(nv, 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 2048), [&](const auto& r) {
        for (std::size_t v = r.begin(); v != r.end(); ++v) lock_[v] = !closed_fan(std::uint32_t(v));
    });
    for (std::size_t v = 0; v < nv; ++v) locked_ += lock_[v] && vcount_[v] > 0;
    if (frozen)
        for (std::size_t v = 0; v < nv; ++v) lock_[v] |= (*frozen)[v];
}

bool Collapser::topology_ok(std::uint32_t v, std::uint32_t w, const std::vector<std::uint32_t>& rv) {
    int shared = 0;
    for_faces(v, [&](std::uint32_t f) { shared += (T_[f][0] == w) + (T_[f][1] == w) + (T_[f][2] == w); });
    if (shared != 2) return false;
    // Link condition: v and w have exactly the two opposite vertices in common.
    ring(w, rw_);
    int common = 0;
    for (auto x : rv)
        if (std::find(rw_.begin(), rw_.end(), x) != rw_.end()) ++common;
    if (common != 2) return false;
    if (rv.size() == 3 && rw_.size() == 3) return false;
    if (rv.size() == 3) {
        // The face left over must not exist already.
        std::uint32_t a = kNone, b = kNone;
        for (auto x : rv)
            if (x != w) (a == kNone ? a : b) = x;
        bool dup = false;
        for_faces(w, [&](std::uint32_t f) {
            const auto& t = T_[f];
            const bool ha = t[0] == a || t[1] == a || t[2] == a, hb = t[0] == b || t[1] == b || t[2] == b;
            dup |= ha && hb;
        });
        if (dup) return false;
    }
    return true;
}

void Collapser::old_faces(std::uint32_t v, std::vector<OldFace>& out) const {
    out.clear();
    for_faces(v, [&](std::uint32_t f) {
        const auto& t = T_[f];
        const Vec3d n = cross_of(Vec3d(P_[t[0]]), Vec3d(P_[t[1]]), Vec3d(P_[t[2]]));
        out.push_back({n, length(n)});
    });
}

bool Collapser::geometry_ok(std::uint32_t v, std::uint32_t w, double cos_limit, double max_aspect, double& min_cos,
                            const std::vector<OldFace>& old, double give_up_below) const {
    min_cos = 1.0;
    const Vec3d pw(P_[w]);
    bool ok = true;
    std::size_t k = 0; // v's face, in for_faces order
    for_faces(v, [&](std::uint32_t f) {
        const OldFace& o = old[k++];
        if (!ok) return;
        const auto& t = T_[f];
        if (t[0] == w || t[1] == w || t[2] == w) return;
        Vec3d q[3];
        for (int i = 0; i < 3; ++i) q[i] = t[i] == v ? pw : Vec3d(P_[t[i]]);
        const Vec3d n = cross_of(q[0], q[1], q[2]);
        const double len = length(n);
        const double scale = std::max({dot(q[1] - q[0], q[1] - q[0]), dot(q[2] - q[0], q[2] - q[0])});
        if (!(len > 1e-12 * scale)) {
            ok = false;
            return;
        }
        const double c = dot(n, o.n) / (len * o.len);
        min_cos = std::min(min_cos, c);
        if (c < cos_limit || c < give_up_below) {
            ok = false;
            return;
        }
        if (max_aspect > 0) {
            const double an = aspect_ratio(q[0], q[1], q[2]);
            if (an > max_aspect) {
                const double ao = aspect_ratio(Vec3d(P_[t[0]]), Vec3d(P_[t[1]]), Vec3d(P_[t[2]]));
                if (an > ao) ok = false;
            }
        }
    });
    return ok;
}

void Collapser::collapse(std::uint32_t v, std::uint32_t w) {
    const std::uint32_t start = std::uint32_t(refs_.size());
    for_faces(w, [&](std::uint32_t f) {
        auto& t = T_[f];
        if (t[0] == v || t[1] == v || t[2] == v) {
            t[0] = kNone; // dead
            --alive_faces_;
        } else {
            refs_.push_back(f);
        }
    });
    for_faces(v, [&](std::uint32_t f) {
        auto& t = T_[f];
        for (int k = 0; k < 3; ++k)
            if (t[k] == v) t[k] = w;
        normals_[f] = face_normal(f);
        refs_.push_back(f);
    });
    vstart_[w] = start;
    vcount_[w] = std::uint32_t(refs_.size()) - start;
    vdead_[v] = 1;
    vcount_[v] = 0;
    if (refs_.size() > 3 * initial_refs_) build_lists();
}

void Collapser::finish() {
    const std::size_t nv = P_.size();
    std::vector<std::uint32_t> order(nv, kNone);
    for (std::size_t f = 0; f < T_.size(); ++f)
        if (T_[f][0] != kNone)
            for (auto i : T_[f]) order[i] = 0;
    // Survivors keep their relative order (stable for attributes).
    std::uint32_t k = 0;
    for (std::size_t v = 0; v < nv; ++v)
        if (order[v] != kNone) order[v] = k++;
    std::vector<std::array<std::uint32_t, 3>> tris;
    tris.reserve(alive_faces_);
    for (std::size_t f = 0; f < T_.size(); ++f)
        if (T_[f][0] != kNone) tris.push_back({order[T_[f][0]], order[T_[f][1]], order[T_[f][2]]});
    auto compact = [&](auto& vec) {
        if (vec.size() != nv) {
            vec.clear();
            return;
        }
        std::size_t o = 0;
        for (std::size_t v = 0; v < nv; ++v)
            if (order[v] != kNone) vec[o++] = vec[v];
        vec.resize(o);
    };
    compact(mesh_.positions);
    compact(mesh_.uvs);
    compact(mesh_.colors);
    const bool had_normals = !mesh_.normals.empty();
    mesh_.normals.clear();
    mesh_.triangles = std::move(tris);
    if (had_normals) mesh_.compute_normals();
}

bool Collapser::closed_fan(std::uint32_t v) const {
    // Well above the valence of a candidate (64, see the scores), so a vertex that grew
    // that large in an earlier pass (reduce_blocked) can still take collapses, as in one pass.
    constexpr int kMax = 256;
    std::uint32_t nxt[kMax], prv[kMax];
    int n = 0;
    bool ok = true;
    for_faces(v, [&](std::uint32_t f) {
        const auto& t = T_[f];
        const int k = t[0] == v ? 0 : (t[1] == v ? 1 : 2);
        if (n == kMax || t[(k + 1) % 3] == v || t[(k + 2) % 3] == v) {
            ok = false;
            return;
        }
        nxt[n] = t[(k + 1) % 3];
        prv[n] = t[(k + 2) % 3];
        ++n;
    });
    if (!ok || n < 3) return false;
    // Each neighbour once as "next" and once as "previous", and one cycle through all.
    for (int i = 0; i < n; ++i) {
        int as_next = 0, as_prev = 0;
        for (int j = 0; j < n; ++j) {
            as_next += nxt[j] == nxt[i];
            as_prev += prv[j] == nxt[i];
        }
        if (as_next != 1 || as_prev != 1) return false;
    }
    int steps = 0, i = 0;
    do {
        const std::uint32_t x = nxt[i];
        int j = 0;
        while (prv[j] != x) ++j;
        i = j;
        ++steps;
    } while (i != 0 && steps <= n);
    return steps == n;
}

void Collapser::build_lists() {
    const std::size_t nv = P_.size();
    vstart_.assign(nv, 0);
    vcount_.assign(nv, 0);
    for (std::size_t f = 0; f < T_.size(); ++f)
        if (T_[f][0] != kNone)
            for (int k = 0; k < 3; ++k) ++vcount_[T_[f][k]];
    std::uint32_t acc = 0;
    for (std::size_t v = 0; v < nv; ++v) {
        vstart_[v] = acc;
        acc += vcount_[v];
    }
    refs_.assign(acc, 0);
    std::vector<std::uint32_t> fill(vstart_);
    for (std::size_t f = 0; f < T_.size(); ++f)
        if (T_[f][0] != kNone)
            for (int k = 0; k < 3; ++k) refs_[fill[T_[f][k]]++] = std::uint32_t(f);
    refs_.reserve(std::size_t(acc) * 3 + 64);
    initial_refs_ = std::max<std::size_t>(acc, 64);
}

// The vertex queue.

void VertexHeap::build(const std::vector<std::uint32_t>& vs, const std::vector<float>& keys) {
    heap_.resize(vs.size());
    for (std::size_t i = 0; i < vs.size(); ++i) {
        heap_[i] = {keys[vs[i]], vs[i]};
        pos_[vs[i]] = std::uint32_t(i);
    }
    for (std::size_t i = heap_.size() / 4 + 1; i-- > 0;) down(i);
}

void VertexHeap::set(std::uint32_t v, float k) {
    if (pos_[v] == kNone) {
        pos_[v] = std::uint32_t(heap_.size());
        heap_.push_back({k, v});
        up(heap_.size() - 1);
        return;
    }
    const std::uint32_t i = pos_[v];
    const float old = heap_[i].key;
    heap_[i].key = k;
    if (k < old) up(i);
    else down(i);
}

void VertexHeap::erase(std::uint32_t v) {
    const std::uint32_t i = pos_[v];
    if (i == kNone) return;
    pos_[v] = kNone;
    const Node last = heap_.back();
    heap_.pop_back();
    if (i == heap_.size()) return;
    heap_[i] = last;
    pos_[last.v] = i;
    up(i);
    down(pos_[last.v]);
}

void VertexHeap::up(std::size_t i) {
    const Node n = heap_[i];
    while (i > 0) {
        const std::size_t parent = (i - 1) / 4;
        if (!(n.key < heap_[parent].key)) break;
        place(i, heap_[parent]);
        i = parent;
    }
    place(i, n);
}

void VertexHeap::down(std::size_t i) {
    const std::size_t size = heap_.size();
    if (i >= size) return;
    const Node n = heap_[i];
    for (;;) {
        const std::size_t c0 = 4 * i + 1;
        if (c0 >= size) break;
        std::size_t best = c0;
        const std::size_t ce = std::min(c0 + 4, size);
        for (std::size_t c = c0 + 1; c < ce; ++c)
            if (heap_[c].key < heap_[best].key) best = c;
        if (!(heap_[best].key < n.key)) break;
        place(i, heap_[best]);
        i = best;
    }
    place(i, n);
}

} // namespace cm::decimate
