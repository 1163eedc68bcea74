#include "mesh_decimate.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "geometry/mesh_intersect.h"

namespace cm {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr std::uint32_t kNone = 0xffffffffu;

Vec3d cross_of(const Vec3d& a, const Vec3d& b, const Vec3d& c) { return cross(b - a, c - a); }

/// sqrt(3) L_max^2 / (4 A): 1 for an equilateral triangle, large for slivers.
double aspect_ratio(const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    const double l = std::max({dot(b - a, b - a), dot(c - b, c - b), dot(a - c, a - c)});
    const double area2 = length(cross_of(a, b, c));   // twice the area
    return area2 > 0 ? std::sqrt(3.0) * l / (2.0 * area2) : HUGE_VAL;
}

// The collapse engine: triangles, per-vertex face lists (start/count into one
// growing array of face ids; a vertex's list is rewritten at the end when it
// changes), per-face unit normals, and the validity checks.
class Collapser {
public:
    /// `frozen` (optional, per vertex): vertices that must stay, on top of the locked ones.
    Collapser(Mesh& m, const std::vector<char>* frozen) : mesh_(m), P_(m.positions), T_(m.triangles) {
        const std::size_t nv = P_.size(), nf = T_.size();
        vdead_.assign(nv, 0);
        alive_faces_ = nf;
        build_lists();
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

    std::size_t alive_faces() const { return alive_faces_; }
    std::size_t locked() const { return locked_; }
    bool usable(std::uint32_t v) const { return !vdead_[v] && !lock_[v]; }
    const Vec3f& point(std::uint32_t v) const { return P_[v]; }
    /// Unit normal of face f, from the positions (not stored: the positions are read
    /// anyway, and one array less keeps the random accesses of the queue in cache).
    Vec3f normal(std::uint32_t f) const { return face_normal(f); }
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
    bool topology_ok(std::uint32_t v, std::uint32_t w, const std::vector<std::uint32_t>& rv) {
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

    /// Geometry of collapsing v into w: no changed face may lose its area, turn by more
    /// than acos(cos_limit) or become thinner than max_aspect (unless it was already).
    /// On success `min_cos` is the smallest cosine between a changed face's old and new normal.
    bool geometry_ok(std::uint32_t v, std::uint32_t w, double cos_limit, double max_aspect, double& min_cos) const {
        min_cos = 1.0;
        const Vec3d pw(P_[w]);
        bool ok = true;
        for_faces(v, [&](std::uint32_t f) {
            if (!ok) return;
            const auto& t = T_[f];
            if (t[0] == w || t[1] == w || t[2] == w) return;
            Vec3d q[3];
            for (int k = 0; k < 3; ++k) q[k] = t[k] == v ? pw : Vec3d(P_[t[k]]);
            const Vec3d n = cross_of(q[0], q[1], q[2]);
            const double len = length(n);
            const double scale = std::max({dot(q[1] - q[0], q[1] - q[0]), dot(q[2] - q[0], q[2] - q[0])});
            if (!(len > 1e-12 * scale)) { ok = false; return; }
            const Vec3d n_old = cross_of(Vec3d(P_[t[0]]), Vec3d(P_[t[1]]), Vec3d(P_[t[2]]));
            const double c = dot(n, n_old) / (len * length(n_old));
            min_cos = std::min(min_cos, c);
            if (c < cos_limit) { ok = false; return; }
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

    /// Collapses v into w (checked before). Returns nothing; w's face list is rewritten.
    void collapse(std::uint32_t v, std::uint32_t w) {
        const std::uint32_t start = std::uint32_t(refs_.size());
        for_faces(w, [&](std::uint32_t f) {
            auto& t = T_[f];
            if (t[0] == v || t[1] == v || t[2] == v) {
                t[0] = kNone;   // dead
                --alive_faces_;
            } else {
                refs_.push_back(f);
            }
        });
        for_faces(v, [&](std::uint32_t f) {
            auto& t = T_[f];
            for (int k = 0; k < 3; ++k)
                if (t[k] == v) t[k] = w;
            refs_.push_back(f);
        });
        vstart_[w] = start;
        vcount_[w] = std::uint32_t(refs_.size()) - start;
        vdead_[v] = 1;
        vcount_[v] = 0;
        if (refs_.size() > 3 * initial_refs_) build_lists();
    }

    /// Drops dead faces and unused vertices from the mesh.
    void finish() {
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
            if (vec.size() != nv) { vec.clear(); return; }
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

private:
    bool closed_fan(std::uint32_t v) const {
        constexpr int kMax = 64;
        std::uint32_t nxt[kMax], prv[kMax];
        int n = 0;
        bool ok = true;
        for_faces(v, [&](std::uint32_t f) {
            const auto& t = T_[f];
            const int k = t[0] == v ? 0 : (t[1] == v ? 1 : 2);
            if (n == kMax || t[(k + 1) % 3] == v || t[(k + 2) % 3] == v) { ok = false; return; }
            nxt[n] = t[(k + 1) % 3];
            prv[n] = t[(k + 2) % 3];
            ++n;
        });
        if (!ok || n < 3) return false;
        // Each neighbour once as "next" and once as "previous", and one cycle through all.
        for (int i = 0; i < n; ++i) {
            int as_next = 0, as_prev = 0;
            for (int j = 0; j < n; ++j) { as_next += nxt[j] == nxt[i]; as_prev += prv[j] == nxt[i]; }
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

    Vec3f face_normal(std::uint32_t f) const {
        const auto& t = T_[f];
        return Vec3f(normalize(cross_of(Vec3d(P_[t[0]]), Vec3d(P_[t[1]]), Vec3d(P_[t[2]]))));
    }

    void build_lists() {
        const std::size_t nv = P_.size();
        vstart_.assign(nv, 0);
        vcount_.assign(nv, 0);
        for (std::size_t f = 0; f < T_.size(); ++f)
            if (T_[f][0] != kNone)
                for (int k = 0; k < 3; ++k) ++vcount_[T_[f][k]];
        std::uint32_t acc = 0;
        for (std::size_t v = 0; v < nv; ++v) { vstart_[v] = acc; acc += vcount_[v]; }
        refs_.assign(acc, 0);
        std::vector<std::uint32_t> fill(vstart_);
        for (std::size_t f = 0; f < T_.size(); ++f)
            if (T_[f][0] != kNone)
                for (int k = 0; k < 3; ++k) refs_[fill[T_[f][k]]++] = std::uint32_t(f);
        refs_.reserve(std::size_t(acc) * 3 + 64);
        initial_refs_ = std::max<std::size_t>(acc, 64);
    }

    Mesh& mesh_;
    std::vector<Vec3f>& P_;
    std::vector<std::array<std::uint32_t, 3>>& T_;
    std::vector<char> vdead_, lock_;
    std::vector<std::uint32_t> vstart_, vcount_, refs_;
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
    void build(const std::vector<std::uint32_t>& vs, const std::vector<float>& keys) {
        heap_.resize(vs.size());
        for (std::size_t i = 0; i < vs.size(); ++i) {
            heap_[i] = {keys[vs[i]], vs[i]};
            pos_[vs[i]] = std::uint32_t(i);
        }
        for (std::size_t i = heap_.size() / 4 + 1; i-- > 0;) down(i);
    }
    void set(std::uint32_t v, float k) {
        if (pos_[v] == kNone) {
            pos_[v] = std::uint32_t(heap_.size());
            heap_.push_back({k, v});
            up(heap_.size() - 1);
            return;
        }
        const std::uint32_t i = pos_[v];
        const float old = heap_[i].key;
        heap_[i].key = k;
        if (k < old) up(i); else down(i);
    }
    void erase(std::uint32_t v) {
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
    void pop() { erase(heap_[0].v); }

private:
    struct Node {
        float key;
        std::uint32_t v;
    };
    void place(std::size_t i, const Node& n) { heap_[i] = n; pos_[n.v] = std::uint32_t(i); }
    void up(std::size_t i) {
        const Node n = heap_[i];
        while (i > 0) {
            const std::size_t parent = (i - 1) / 4;
            if (!(n.key < heap_[parent].key)) break;
            place(i, heap_[parent]);
            i = parent;
        }
        place(i, n);
    }
    void down(std::size_t i) {
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

    std::vector<Node> heap_;
    std::vector<std::uint32_t> pos_;
};

// Runs the queue: `score(v, ring, key)` says whether v is a candidate and its key;
// `choose(v, ring, w, key)` picks the target of v's collapse (false: none now, the
// vertex waits until a neighbour changes), and may raise the key (then the vertex
// is queued again instead). `after(v, w, key)` follows each collapse.
template <typename Score, typename Choose, typename After>
std::size_t run_queue(Collapser& c, std::size_t nv, std::size_t target_faces, float stop_key,
                      const std::function<void(double)>& progress, Score&& score, Choose&& choose, After&& after) {
    std::vector<float> keys(nv);
    std::vector<char> cand(nv, 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 2048), [&](const auto& r) {
        std::vector<std::uint32_t> ring;
        for (std::size_t v = r.begin(); v != r.end(); ++v) {
            float k;
            if (c.usable(std::uint32_t(v)) && score(std::uint32_t(v), ring, k)) { keys[v] = k; cand[v] = 1; }
        }
    });
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
            if (c.usable(v) && score(v, scratch, k)) heap.set(v, k); else heap.erase(v);
            continue;
        }
        heap.pop();
        c.ring(v, rv);
        std::uint32_t w;
        float key = key0;
        if (!choose(v, rv, w, key)) continue;
        if (key > key0) { heap.set(v, key); continue; }
        c.collapse(v, w);
        ++collapses;
        after(v, w, key);
        // The faces around every vertex of v's old ring (w included) changed.
        for (auto x : rv) {
            if (heap.contains(x)) { dirty[x] = 1; continue; }
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

// One reduction run (see reduce_mesh).
DecimateStats reduce_once(Mesh& mesh, const ReduceOptions& opt, const std::vector<char>* frozen) {
    DecimateStats st;
    st.faces_before = mesh.face_count();
    Collapser c(mesh, frozen);
    st.locked_vertices = c.locked();
    const double limit = opt.max_angle_deg * kPi / 180.0;
    const double cos_limit = std::cos(limit);
    // Candidate test and importance: theta = the largest angle between two face normals
    // around v; I = theta * sum_j |V_j - V|. A small multiple of the perimeter orders
    // the exactly flat vertices (theta = 0) shortest-edges first.
    auto score = [&](std::uint32_t v, std::vector<std::uint32_t>&, float& key) {
        constexpr int kMax = 64;
        Vec3f normals[kMax];
        int n = 0;
        double L = 0;
        const Vec3f p = c.point(v);
        bool many = false;
        c.for_faces(v, [&](std::uint32_t f) {
            if (n == kMax) { many = true; return; }
            normals[n++] = c.normal(f);
            const auto& t = c.tri(f);
            const std::uint32_t next = t[0] == v ? t[1] : (t[1] == v ? t[2] : t[0]);
            L += length(c.point(next) - p);
        });
        if (many || n < 3) return false;
        float min_dot = 1.0f;
        for (int i = 0; i < n; ++i)
            for (int j = i + 1; j < n; ++j) min_dot = std::min(min_dot, dot(normals[i], normals[j]));
        const double theta = std::acos(std::clamp(double(min_dot), -1.0, 1.0));
        if (!(theta < limit)) return false;
        key = float(theta * L + 1e-4 * L);
        return true;
    };
    // The target: among the neighbours whose collapse passes the geometric guards, the one
    // that turns the faces least (then the nearest); topology is checked in that order.
    struct Option { double cos, len; std::uint32_t w; };
    std::vector<Option> options;
    auto choose = [&](std::uint32_t v, const std::vector<std::uint32_t>& rv, std::uint32_t& w, float&) {
        options.clear();
        const Vec3d p(c.point(v));
        for (auto x : rv) {
            double mc;
            if (!c.usable(x) || !c.geometry_ok(v, x, cos_limit, opt.max_aspect_ratio, mc)) continue;
            options.push_back({mc, length(Vec3d(c.point(x)) - p), x});
        }
        std::sort(options.begin(), options.end(), [](const Option& a, const Option& b) {
            if (std::fabs(a.cos - b.cos) > 1e-9) return a.cos > b.cos;
            return a.len < b.len;
        });
        for (const auto& o : options)
            if (c.topology_ok(v, o.w, rv)) { w = o.w; return true; }
        return false;
    };
    st.collapses = run_queue(c, mesh.positions.size(), opt.target_faces, HUGE_VALF, opt.progress, score, choose,
                             [](std::uint32_t, std::uint32_t, float) {});
    c.finish();
    st.faces_after = mesh.face_count();
    return st;
}

// Symmetric 4x4 quadric: a2 ab ac ad b2 bc bd c2 cd d2.
struct Quadric {
    double q[10] = {};
    void add_plane(const Vec3d& n, double d, double w) {
        const double a = n.x, b = n.y, c = n.z;
        const double v[10] = {a * a, a * b, a * c, a * d, b * b, b * c, b * d, c * c, c * d, d * d};
        for (int i = 0; i < 10; ++i) q[i] += w * v[i];
    }
    Quadric& operator+=(const Quadric& o) {
        for (int i = 0; i < 10; ++i) q[i] += o.q[i];
        return *this;
    }
    double eval(const Vec3d& p) const {
        const double x = p.x, y = p.y, z = p.z;
        return q[0] * x * x + 2 * q[1] * x * y + 2 * q[2] * x * z + 2 * q[3] * x + q[4] * y * y + 2 * q[5] * y * z +
               2 * q[6] * y + q[7] * z * z + 2 * q[8] * z + q[9];
    }
};

DecimateStats quadric_once(Mesh& mesh, const QuadricOptions& opt, const std::vector<char>* frozen) {
    DecimateStats st;
    st.faces_before = mesh.face_count();
    const std::size_t nv = mesh.positions.size();
    // Plane quadrics, area weighted, summed per vertex.
    std::vector<Quadric> Q(nv);
    for (const auto& t : mesh.triangles) {
        const Vec3d a(mesh.positions[t[0]]), b(mesh.positions[t[1]]), cc(mesh.positions[t[2]]);
        const Vec3d n2 = cross_of(a, b, cc);
        const double len = length(n2);
        if (!(len > 0)) continue;
        const Vec3d n = n2 / len;
        for (int k = 0; k < 3; ++k) Q[t[k]].add_plane(n, -dot(n, a), 0.5 * len);
    }
    Collapser c(mesh, frozen);
    st.locked_vertices = c.locked();
    const double cos_limit = std::cos(opt.max_normal_deviation_deg * kPi / 180.0);
    const double max_err2 = opt.max_error > 0 ? opt.max_error * opt.max_error : HUGE_VAL;
    // Errors are normalised by the area of the quadric (sum of weights of the planes) so
    // that the key is a squared distance.
    auto cost = [&](std::uint32_t v, std::uint32_t w) {
        Quadric s = Q[v];
        s += Q[w];
        return std::max(0.0, s.eval(Vec3d(c.point(w))));
    };
    auto area_of = [&](std::uint32_t v, std::uint32_t w) {
        // q[0] + q[4] + q[7] = sum of weights * |n|^2 = total area weight
        return std::max(1e-30, Q[v].q[0] + Q[v].q[4] + Q[v].q[7] + Q[w].q[0] + Q[w].q[4] + Q[w].q[7]);
    };
    auto score = [&](std::uint32_t v, std::vector<std::uint32_t>& ring, float& key) {
        c.ring(v, ring);
        double best = HUGE_VAL;
        for (auto x : ring)
            if (c.usable(x)) best = std::min(best, cost(v, x) / area_of(v, x));
        if (!(best < HUGE_VAL)) return false;
        key = float(best);
        return true;
    };
    // The cheapest neighbour that passes the guards; costs first (cheap), checks in order.
    std::vector<std::pair<double, std::uint32_t>> options;
    auto choose = [&](std::uint32_t v, const std::vector<std::uint32_t>& rv, std::uint32_t& w, float& key) {
        options.clear();
        for (auto x : rv)
            if (c.usable(x)) options.push_back({cost(v, x) / area_of(v, x), x});
        std::sort(options.begin(), options.end());
        for (const auto& [e, x] : options) {
            double mc;
            if (!c.geometry_ok(v, x, cos_limit, opt.max_aspect_ratio, mc) || !c.topology_ok(v, x, rv)) continue;
            w = x;
            key = std::max(key, float(e));
            return true;
        }
        return false;
    };
    double max_err = 0;
    st.collapses = run_queue(c, nv, opt.target_faces, float(max_err2), opt.progress, score, choose,
                             [&](std::uint32_t v, std::uint32_t w, float key) {
                                 Q[w] += Q[v];
                                 max_err = std::max(max_err, double(key));
                             });
    c.finish();
    st.max_error = std::sqrt(max_err);
    st.faces_after = mesh.face_count();
    return st;
}

// Runs `once` and, while the result has faces crossing each other, runs it again from
// the input with the input vertices frozen where those faces cross (the overlap of the two
// faces' boxes, grown by a quarter). Frozen regions only grow and stay as the input had
// them, so the loop ends; it also stops when a restart removes nothing.
template <typename Once>
DecimateStats without_crossings(const Mesh& input, Mesh& mesh, bool enabled, Once&& once) {
    mesh = input;
    if (!enabled) return once(mesh, nullptr);
    constexpr std::size_t kMaxRestarts = 6;
    std::vector<char> frozen;
    std::size_t last = SIZE_MAX;
    for (std::size_t restart = 0;; ++restart) {
        DecimateStats st = once(mesh, restart ? &frozen : nullptr);
        const std::vector<FacePair> pairs = find_self_intersections(mesh);
        st.restarts = restart;
        st.crossings_left = pairs.size();
        st.frozen_vertices = std::size_t(std::count(frozen.begin(), frozen.end(), char(1)));
        if (pairs.empty() || restart == kMaxRestarts || pairs.size() >= last) return st;
        last = pairs.size();
        // The region of each crossing: where the two faces' boxes overlap, grown a little.
        std::vector<std::array<Vec3f, 2>> boxes;
        for (const auto& pr : pairs) {
            std::array<Vec3f, 2> fb[2];
            for (int i = 0; i < 2; ++i) {
                const auto& t = mesh.triangles[pr[std::size_t(i)]];
                fb[i] = {vmin(mesh.positions[t[0]], vmin(mesh.positions[t[1]], mesh.positions[t[2]])),
                         vmax(mesh.positions[t[0]], vmax(mesh.positions[t[1]], mesh.positions[t[2]]))};
            }
            const Vec3f lo = vmax(fb[0][0], fb[1][0]), hi = vmin(fb[0][1], fb[1][1]);
            const float small = std::min(length(fb[0][1] - fb[0][0]), length(fb[1][1] - fb[1][0]));
            const float grow = 0.25f * std::max(length(hi - lo), 0.25f * small);
            const Vec3f g(grow, grow, grow);
            boxes.push_back({lo - g, hi + g});
        }
        frozen.resize(input.positions.size(), 0);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, input.positions.size(), 4096), [&](const auto& r) {
            for (std::size_t v = r.begin(); v != r.end(); ++v) {
                const Vec3f& p = input.positions[v];
                for (const auto& b : boxes)
                    if (p.x >= b[0].x && p.x <= b[1].x && p.y >= b[0].y && p.y <= b[1].y && p.z >= b[0].z &&
                        p.z <= b[1].z) {
                        frozen[v] = 1;
                        break;
                    }
            }
        });
        mesh = input;
    }
}

} // namespace

DecimateStats reduce_mesh(const Mesh& input, Mesh& out, const ReduceOptions& opt) {
    return without_crossings(input, out, opt.no_crossings,
                             [&](Mesh& m, const std::vector<char>* frozen) { return reduce_once(m, opt, frozen); });
}

DecimateStats reduce_mesh(Mesh& mesh, const ReduceOptions& opt) {
    const Mesh input = std::move(mesh);
    return reduce_mesh(input, mesh, opt);
}

DecimateStats quadric_decimate(const Mesh& input, Mesh& out, const QuadricOptions& opt) {
    return without_crossings(input, out, opt.no_crossings,
                             [&](Mesh& m, const std::vector<char>* frozen) { return quadric_once(m, opt, frozen); });
}

DecimateStats quadric_decimate(Mesh& mesh, const QuadricOptions& opt) {
    const Mesh input = std::move(mesh);
    return quadric_decimate(input, mesh, opt);
}

} // namespace cm
