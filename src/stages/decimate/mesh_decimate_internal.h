// Internals of the polygon reduction (mesh_decimate.h), shared by its files: the
// collapse engine (Collapser, mesh_decimate_collapse.cpp), the vertex queue (VertexHeap,
// run_queue), the paper's ordering (mesh_decimate.cpp) and its rounds in blocks
// (mesh_decimate_blocks.cpp), and the quadric ordering (mesh_decimate_quadric.cpp).
#pragma once
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "mesh_decimate.h"

namespace cm::decimate {

constexpr double kPi = 3.14159265358979323846;
constexpr std::uint32_t kNone = 0xffffffffu;

inline Vec3d cross_of(const Vec3d& a, const Vec3d& b, const Vec3d& c) { return cross(b - a, c - a); }

// The collapse engine: triangles, per-vertex face lists (start/count into one
// growing array of face ids; a vertex's list is rewritten at the end when it
// changes), per-face unit normals, and the validity checks.
class Collapser {
public:
    /// `frozen` (optional, per vertex): vertices that must stay, on top of the locked ones.
    /// `locks` (optional): locks() of a collapser built before over the same mesh and
    /// `frozen`, taken instead of finding them again.
    Collapser(Mesh& m, const std::vector<char>* frozen, const std::vector<char>* locks = nullptr);
    /// Per vertex: whether it may not go (its fan is not closed and consistently oriented, or frozen).
    const std::vector<char>& locks() const { return lock_; }

    std::size_t alive_faces() const { return alive_faces_; }
    std::size_t locked() const { return locked_; }
    bool usable(std::uint32_t v) const { return !vdead_[v] && !lock_[v]; }
    const Vec3f& point(std::uint32_t v) const { return P_[v]; }
    /// Unit normal of face f (kept per face: the importance of a vertex reads those of
    /// its faces, and a face's normal changes only when a collapse moves its corner).
    Vec3f normal(std::uint32_t f) const { return normals_[f]; }
    const std::array<std::uint32_t, 3>& tri(std::uint32_t f) const { return T_[f]; }

    template <typename F>
    void for_faces(std::uint32_t v, F&& f) const {
        const std::uint32_t b = vstart_[v], e = b + vcount_[v];
        for (std::uint32_t i = b; i < e; ++i)
            if (T_[refs_[i]][0] != kNone) f(refs_[i]);
    }

    /// Neighbours of a usable vertex: its fan is closed and consistently oriented, so each
    /// neighbour follows v in exactly one of its faces.
    void ring(std::uint32_t v, std::vector<std::uint32_t>& out) const {
        out.clear();
        for_faces(v, [&](std::uint32_t f) {
            const auto& t = T_[f];
            out.push_back(t[0] == v ? t[1] : (t[1] == v ? t[2] : t[0]));
        });
    }

    /// Topology of collapsing v into its neighbour w (`rv` is ring(v)): the edge has two
    /// faces, the link condition holds, and no tetrahedron-like pocket folds shut.
    bool topology_ok(std::uint32_t v, std::uint32_t w, const std::vector<std::uint32_t>& rv);

    /// The faces of v (in for_faces order) as they are before a collapse: their normals
    /// (unnormalised) and those normals' lengths, the same for every target of v.
    struct OldFace {
        Vec3d n;
        double len;
    };
    void old_faces(std::uint32_t v, std::vector<OldFace>& out) const;
    /// Geometry of collapsing v into w: no changed face may lose its area, turn by more
    /// than acos(cos_limit) or become thinner than max_aspect (unless it was already).
    /// On success `min_cos` is the smallest cosine between a changed face's old and new normal.
    /// `old` is old_faces(v). With `give_up_below`, false as soon as a face's cosine is below
    /// it (a target that cannot beat one already found is not followed to the end).
    bool geometry_ok(std::uint32_t v, std::uint32_t w, double cos_limit, double max_aspect, double& min_cos,
                     const std::vector<OldFace>& old, double give_up_below = -2.0) const;

    /// Collapses v into w (checked before). Returns nothing; w's face list is rewritten.
    void collapse(std::uint32_t v, std::uint32_t w);

    /// Drops dead faces and unused vertices from the mesh.
    void finish();

private:
    /// True when v's faces form one consistently oriented closed fan (see the constructor).
    bool closed_fan(std::uint32_t v) const;

    Vec3f face_normal(std::uint32_t f) const {
        const auto& t = T_[f];
        return Vec3f(normalize(cross_of(Vec3d(P_[t[0]]), Vec3d(P_[t[1]]), Vec3d(P_[t[2]]))));
    }

    void build_lists();

    Mesh& mesh_;
    std::vector<Vec3f>& P_;
    std::vector<std::array<std::uint32_t, 3>>& T_;
    std::vector<char> vdead_, lock_;
    std::vector<std::uint32_t> vstart_, vcount_, refs_;
    std::vector<Vec3f> normals_; ///< face_normal() of each face, kept up to date
    std::vector<std::uint32_t> rw_;
    std::size_t alive_faces_ = 0, initial_refs_ = 0, locked_ = 0;
};

// A 4-ary min-heap of vertices keyed by float, with one entry per vertex, so a
// re-scored vertex moves in place instead of leaving stale copies behind. Keys sit
// in the heap array beside the vertex so the four children share a cache line.
class VertexHeap {
public:
    explicit VertexHeap(std::size_t nv) : pos_(nv, kNone) {}
    bool empty() const { return heap_.empty(); }
    bool contains(std::uint32_t v) const { return pos_[v] != kNone; }
    std::uint32_t top() const { return heap_[0].v; }
    float top_key() const { return heap_[0].key; }
    /// Bulk load (before any other call), then heapify.
    void build(const std::vector<std::uint32_t>& vs, const std::vector<float>& keys);
    void set(std::uint32_t v, float k);
    void erase(std::uint32_t v);
    void pop() { erase(heap_[0].v); }

private:
    struct Node {
        float key;
        std::uint32_t v;
    };
    void place(std::size_t i, const Node& n) {
        heap_[i] = n;
        pos_[n.v] = std::uint32_t(i);
    }
    void up(std::size_t i);
    void down(std::size_t i);

    std::vector<Node> heap_;
    std::vector<std::uint32_t> pos_;
};

// Runs the queue: `score(v, ring, key)` says whether v is a candidate and its key;
// `choose(v, ring, w, key)` picks the target of v's collapse (false: none now, the
// vertex waits until a neighbour changes), and may raise the key (then the vertex
// is queued again instead). `after(v, w, key)` follows each collapse.
/// The starting scores of run_queue: per vertex whether it is a candidate and its key.
struct StartScores {
    std::vector<float> keys;
    std::vector<char> cand;
};
template <typename Score>
StartScores start_scores(const Collapser& c, std::size_t nv, Score&& score) {
    StartScores s{std::vector<float>(nv), std::vector<char>(nv, 0)};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 2048), [&](const auto& r) {
        std::vector<std::uint32_t> ring;
        for (std::size_t v = r.begin(); v != r.end(); ++v) {
            float k;
            if (c.usable(std::uint32_t(v)) && score(std::uint32_t(v), ring, k)) {
                s.keys[v] = k;
                s.cand[v] = 1;
            }
        }
    });
    return s;
}

template <typename Score, typename Choose, typename After>
std::size_t run_queue(Collapser& c, std::size_t nv, std::size_t target_faces, float stop_key, const Progress& progress,
                      Score&& score, Choose&& choose, After&& after, StartScores* start = nullptr) {
    StartScores own;
    if (!start) {
        own = start_scores(c, nv, score);
        start = &own;
    }
    const std::vector<float>& keys = start->keys;
    const std::vector<char>& cand = start->cand;
    std::vector<std::uint32_t> init;
    init.reserve(nv);
    for (std::size_t v = 0; v < nv; ++v)
        if (cand[v]) init.push_back(std::uint32_t(v));
    VertexHeap heap(nv);
    heap.build(init, keys);

    const std::size_t start_faces = c.alive_faces();
    const std::size_t span = start_faces > target_faces ? start_faces - target_faces : 1;
    std::size_t collapses = 0, next_report = 0;
    std::vector<std::uint32_t> rv, scratch;
    // Lazy re-scoring: a collapse marks the vertices around it dirty; a dirty vertex
    // is re-scored when it reaches the top, and goes back in the queue if its key moved.
    // Vertices outside the queue (not candidates, or waiting) are scored at once.
    std::vector<char> dirty(nv, 0);
    while (!heap.empty() && c.alive_faces() > target_faces) {
        const std::uint32_t v = heap.top();
        const float key0 = heap.top_key();
        if (key0 > stop_key) break;
        if (dirty[v]) {
            dirty[v] = 0;
            float k;
            if (c.usable(v) && score(v, scratch, k)) heap.set(v, k);
            else heap.erase(v);
            continue;
        }
        heap.pop();
        c.ring(v, rv);
        std::uint32_t w;
        float key = key0;
        if (!choose(v, rv, w, key)) continue;
        if (key > key0) {
            heap.set(v, key);
            continue;
        }
        c.collapse(v, w);
        ++collapses;
        after(v, w, key);
        // The faces around every vertex of v's old ring (w included) changed.
        for (auto x : rv) {
            if (heap.contains(x)) {
                dirty[x] = 1;
                continue;
            }
            float k;
            if (c.usable(x) && score(x, scratch, k)) heap.set(x, k);
        }
        if (progress && collapses >= next_report) {
            progress(double(start_faces - c.alive_faces()) / double(span));
            next_report = collapses + 4096;
        }
    }
    return collapses;
}

/// The blocks' pass of the reduction (reduce_round), in place of run_queue: one sweep over
/// the candidates whose starting key is at most `stop_key`, in the order of those keys. A
/// vertex whose faces no collapse has changed since the start keeps its starting key; the
/// others are scored again when their turn comes. Each goes when it is still a candidate
/// under `stop_key` and `choose` finds it a target; one that cannot go is not asked again
/// (the rounds after, and the last queue, take what is left). Under the quantile the blocks
/// stop at the order hardly matters (docs/results/speed.md), and this pass keeps no heap and
/// scores no neighbour of a collapse but the ones still to come.
template <typename Score, typename Choose>
std::size_t run_sweep(Collapser& c, const StartScores& start, float stop_key, Score&& score, Choose&& choose) {
    const std::size_t nv = start.keys.size();
    // (key, vertex) in one word: keys are not negative, so their bits order as the keys do.
    std::vector<std::uint64_t> order;
    for (std::size_t v = 0; v < nv; ++v)
        if (start.cand[v] && start.keys[v] <= stop_key)
            order.push_back(std::uint64_t(std::bit_cast<std::uint32_t>(start.keys[v])) << 32 | v);
    std::sort(order.begin(), order.end());
    std::vector<char> touched(nv, 0); // faces changed by a collapse since the start
    std::vector<std::uint32_t> rv, scratch;
    std::size_t collapses = 0;
    for (const std::uint64_t entry : order) {
        const auto v = std::uint32_t(entry);
        if (!c.usable(v)) continue;
        float key = start.keys[v];
        if (touched[v] && (!score(v, scratch, key) || key > stop_key)) continue;
        c.ring(v, rv);
        std::uint32_t w;
        if (!choose(v, rv, w, key)) continue;
        c.collapse(v, w);
        ++collapses;
        for (auto x : rv) touched[x] = 1; // the faces around v's old ring (w among them) changed
    }
    return collapses;
}

// A vertex in the middle of a straight crease: its faces split into two sides, each flat
// within `limit` though the two are not, meeting along exactly two of its edges that continue
// each other within `straight` radians (a, v, b on one line). Such a vertex can go into a or
// b without moving the crease or either side's plane; its importance is its sides' flatness.
struct Crease {
    std::uint32_t a = 0, b = 0;
    double theta = 0; ///< the largest angle between two face normals of one side
};
inline bool straight_crease(const Collapser& c, std::uint32_t v, double limit, double straight, Crease& out) {
    constexpr int kMax = 64;
    if (!(straight > 0)) return false;
    Vec3f normals[kMax];
    std::uint32_t next[kMax], prev[kMax];
    int n = 0;
    bool many = false;
    c.for_faces(v, [&](std::uint32_t f) {
        if (n == kMax) {
            many = true;
            return;
        }
        const auto& t = c.tri(f);
        const int k = t[0] == v ? 0 : (t[1] == v ? 1 : 2);
        normals[n] = c.normal(f);
        next[n] = t[std::size_t((k + 1) % 3)];
        prev[n] = t[std::size_t((k + 2) % 3)];
        ++n;
    });
    if (many || n < 4) return false;
    // The two sides: each face with the nearer of the two normals furthest apart.
    int fi = 0, fj = 0;
    float min_dot = 1.0f;
    for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j)
            if (const float d = dot(normals[i], normals[j]); d < min_dot) min_dot = d, fi = i, fj = j;
    if (double(min_dot) > std::cos(limit)) return false; // flat: the paper's candidate
    int side[kMax];
    for (int i = 0; i < n; ++i) side[i] = dot(normals[i], normals[fi]) >= dot(normals[i], normals[fj]) ? 0 : 1;
    float flat = 1.0f;
    for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j)
            if (side[i] == side[j]) flat = std::min(flat, dot(normals[i], normals[j]));
    out.theta = std::acos(std::clamp(double(flat), -1.0, 1.0));
    if (!(out.theta < limit)) return false;
    // The crease: the edges whose two faces lie on different sides.
    int edges = 0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            if (prev[j] == next[i] && side[i] != side[j]) {
                if (++edges > 2) return false;
                (edges == 1 ? out.a : out.b) = next[i];
            }
    if (edges != 2) return false;
    const Vec3f p = c.point(v), ea = c.point(out.a) - p, eb = c.point(out.b) - p;
    const double la = length(ea), lb = length(eb);
    return la > 0 && lb > 0 && -double(dot(ea, eb)) >= std::cos(straight) * la * lb;
}

// The paper's candidate test and importance of vertex v: theta = the largest angle between
// two face normals around v, under `limit`; I = theta * sum_j |V_j - V|. A small multiple of
// the perimeter orders the exactly flat vertices (theta = 0) shortest-edges first. With
// `straight` (radians, 0: off), a vertex in the middle of a straight crease is a candidate
// too, theta its sides' flatness (straight_crease).
inline bool importance(const Collapser& c, std::uint32_t v, double limit, double straight, float& key) {
    constexpr int kMax = 64;
    // Raw storage: an array of Vec3f would be zeroed (768 bytes) on every call.
    float normals[kMax][3];
    int n = 0;
    double L = 0;
    const Vec3f p = c.point(v);
    bool many = false;
    c.for_faces(v, [&](std::uint32_t f) {
        if (n == kMax) {
            many = true;
            return;
        }
        const Vec3f fn = c.normal(f);
        normals[n][0] = fn.x;
        normals[n][1] = fn.y;
        normals[n][2] = fn.z;
        ++n;
        const auto& t = c.tri(f);
        const std::uint32_t next = t[0] == v ? t[1] : (t[1] == v ? t[2] : t[0]);
        L += length(c.point(next) - p);
    });
    if (many || n < 3) return false;
    float min_dot = 1.0f;
    for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j)
            min_dot = std::min(
                min_dot, normals[i][0] * normals[j][0] + normals[i][1] * normals[j][1] + normals[i][2] * normals[j][2]);
    double theta = std::acos(std::clamp(double(min_dot), -1.0, 1.0));
    if (!(theta < limit)) {
        Crease crease;
        if (!straight_crease(c, v, limit, straight, crease)) return false;
        theta = crease.theta;
    }
    key = float(theta * L + 1e-4 * L);
    return true;
}

/// The queue of one reduction run over the collapser's mesh (see reduce_mesh), down to
/// `target_faces` (0: until no vertex can go) or to the first vertex more important than
/// `stop_key`; returns the collapses made. With `sweep` (and `start`), a block's pass
/// instead: run_sweep up to `stop_key` (no face target).
std::size_t reduce_queue(Collapser& c, std::size_t nv, const ReduceOptions& opt, std::size_t target_faces,
                         float stop_key, const Progress& progress, StartScores* start = nullptr, bool sweep = false);

/// One reduction run over the whole mesh (see reduce_mesh); `frozen` as for Collapser.
DecimateStats reduce_once(Mesh& mesh, const ReduceOptions& opt, const std::vector<char>* frozen,
                          const Progress& progress);

/// reduce_once for large meshes, from `input` into `mesh`, in rounds over spatial blocks
/// (mesh_decimate_blocks.cpp); reduce_once itself for small ones and with a face target.
DecimateStats reduce_blocked(const Mesh& input, Mesh& mesh, const ReduceOptions& opt, const std::vector<char>* frozen,
                             const Progress& progress);

/// One quadric decimation run (see quadric_decimate); `frozen` as for Collapser.
QuadricStats quadric_once(Mesh& mesh, const QuadricOptions& opt, const std::vector<char>* frozen,
                          const Progress& progress);

} // namespace cm::decimate
