#include "core/mesh_decimate.h"

#include <algorithm>
#include <cmath>
#include <queue>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

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
    explicit Collapser(Mesh& m) : mesh_(m), P_(m.positions), T_(m.triangles) {
        const std::size_t nv = P_.size(), nf = T_.size();
        fdead_.assign(nf, 0);
        vdead_.assign(nv, 0);
        alive_faces_ = nf;
        build_lists();
        fn_.resize(nf);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nf, 4096), [&](const auto& r) {
            for (std::size_t f = r.begin(); f != r.end(); ++f) fn_[f] = face_normal(std::uint32_t(f));
        });
        // Lock every vertex whose faces do not form one consistently oriented closed fan
        // (boundary, non-manifold edge or vertex, flipped neighbour, huge valence).
        lock_.assign(nv, 0);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 2048), [&](const auto& r) {
            for (std::size_t v = r.begin(); v != r.end(); ++v) lock_[v] = !closed_fan(std::uint32_t(v));
        });
        for (std::size_t v = 0; v < nv; ++v) locked_ += lock_[v] && vcount_[v] > 0;
    }

    std::size_t alive_faces() const { return alive_faces_; }
    std::size_t locked() const { return locked_; }
    bool usable(std::uint32_t v) const { return !vdead_[v] && !lock_[v]; }
    const Vec3f& point(std::uint32_t v) const { return P_[v]; }
    const Vec3f& normal(std::uint32_t f) const { return fn_[f]; }
    const std::array<std::uint32_t, 3>& tri(std::uint32_t f) const { return T_[f]; }

    template <typename F>
    void for_faces(std::uint32_t v, F&& f) const {
        const std::uint32_t b = vstart_[v], e = b + vcount_[v];
        for (std::uint32_t i = b; i < e; ++i)
            if (!fdead_[refs_[i]]) f(refs_[i]);
    }

    /// Unique neighbours of v.
    void ring(std::uint32_t v, std::vector<std::uint32_t>& out) const {
        out.clear();
        for_faces(v, [&](std::uint32_t f) {
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t x = T_[f][k];
                if (x != v && std::find(out.begin(), out.end(), x) == out.end()) out.push_back(x);
            }
        });
    }

    /// Can v collapse into its neighbour w? `rv` is ring(v). On success, `min_cos` is the
    /// smallest cosine between a changed face's old and new normals.
    bool check(std::uint32_t v, std::uint32_t w, const std::vector<std::uint32_t>& rv, double cos_limit,
               double max_aspect, double& min_cos) {
        if (!usable(w)) return false;
        int shared = 0;
        for_faces(v, [&](std::uint32_t f) { shared += (T_[f][0] == w) + (T_[f][1] == w) + (T_[f][2] == w); });
        if (shared != 2) return false;
        // Link condition: v and w have exactly the two opposite vertices in common.
        ring(w, rw_);
        int common = 0;
        for (auto x : rv)
            if (std::find(rw_.begin(), rw_.end(), x) != rw_.end()) ++common;
        if (common != 2) return false;
        if (rv.size() == 3 || rw_.size() == 3) {
            // A tetrahedron-like pocket: the face left over must not exist already.
            std::uint32_t a = kNone, b = kNone;
            for (auto x : rv)
                if (x != w) (a == kNone ? a : b) = x;
            if (rv.size() == 3) {
                bool dup = false;
                for_faces(w, [&](std::uint32_t f) {
                    const auto& t = T_[f];
                    const bool ha = t[0] == a || t[1] == a || t[2] == a, hb = t[0] == b || t[1] == b || t[2] == b;
                    dup |= ha && hb;
                });
                if (dup) return false;
            }
            if (rv.size() == 3 && rw_.size() == 3) return false;
        }
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
            const double c = dot(n, Vec3d(fn_[f])) / len;
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
                fdead_[f] = 1;
                --alive_faces_;
            } else {
                refs_.push_back(f);
            }
        });
        for_faces(v, [&](std::uint32_t f) {
            auto& t = T_[f];
            for (int k = 0; k < 3; ++k)
                if (t[k] == v) t[k] = w;
            fn_[f] = face_normal(f);
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
            if (!fdead_[f])
                for (auto i : T_[f]) order[i] = 0;
        // Survivors keep their relative order (stable for attributes).
        std::uint32_t k = 0;
        for (std::size_t v = 0; v < nv; ++v)
            if (order[v] != kNone) order[v] = k++;
        std::vector<std::array<std::uint32_t, 3>> tris;
        tris.reserve(alive_faces_);
        for (std::size_t f = 0; f < T_.size(); ++f)
            if (!fdead_[f]) tris.push_back({order[T_[f][0]], order[T_[f][1]], order[T_[f][2]]});
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
            if (!fdead_[f])
                for (int k = 0; k < 3; ++k) ++vcount_[T_[f][k]];
        std::uint32_t acc = 0;
        for (std::size_t v = 0; v < nv; ++v) { vstart_[v] = acc; acc += vcount_[v]; }
        refs_.assign(acc, 0);
        std::vector<std::uint32_t> fill(vstart_);
        for (std::size_t f = 0; f < T_.size(); ++f)
            if (!fdead_[f])
                for (int k = 0; k < 3; ++k) refs_[fill[T_[f][k]]++] = std::uint32_t(f);
        refs_.reserve(std::size_t(acc) * 3 + 64);
        initial_refs_ = std::max<std::size_t>(acc, 64);
    }

    Mesh& mesh_;
    std::vector<Vec3f>& P_;
    std::vector<std::array<std::uint32_t, 3>>& T_;
    std::vector<char> fdead_, vdead_, lock_;
    std::vector<std::uint32_t> vstart_, vcount_, refs_;
    std::vector<Vec3f> fn_;
    std::vector<std::uint32_t> rw_;
    std::size_t alive_faces_ = 0, initial_refs_ = 0, locked_ = 0;
};

struct Entry {
    float key;
    std::uint32_t v;
    std::uint32_t stamp;
    bool operator>(const Entry& o) const { return key > o.key; }
};
using MinQueue = std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>>;

// Runs the queue: `score(v, key)` says whether v is a candidate and its key;
// `choose(v, ring, w, key)` picks the target of v's collapse (false: none now),
// and may raise the key (then the vertex is queued again instead).
template <typename Score, typename Choose, typename After>
std::size_t run_queue(Collapser& c, std::size_t nv, std::size_t target_faces, float stop_key,
                      const std::function<void(double)>& progress, Score&& score, Choose&& choose, After&& after) {
    std::vector<std::uint32_t> stamp(nv, 0);
    std::vector<float> keys(nv);
    std::vector<char> cand(nv, 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 2048), [&](const auto& r) {
        std::vector<std::uint32_t> ring;
        for (std::size_t v = r.begin(); v != r.end(); ++v) {
            float k;
            if (c.usable(std::uint32_t(v)) && score(std::uint32_t(v), ring, k)) { keys[v] = k; cand[v] = 1; }
        }
    });
    std::vector<Entry> init;
    init.reserve(nv);
    for (std::size_t v = 0; v < nv; ++v)
        if (cand[v]) init.push_back({keys[v], std::uint32_t(v), 0});
    MinQueue q(std::greater<Entry>(), std::move(init));

    const std::size_t start_faces = c.alive_faces();
    const std::size_t span = start_faces > target_faces ? start_faces - target_faces : 1;
    std::size_t collapses = 0, next_report = 0;
    std::vector<std::uint32_t> rv, rw;
    while (!q.empty() && c.alive_faces() > target_faces) {
        const Entry e = q.top();
        q.pop();
        if (e.stamp != stamp[e.v] || !c.usable(e.v)) continue;
        if (e.key > stop_key) break;
        c.ring(e.v, rv);
        std::uint32_t w;
        float key = e.key;
        if (!choose(e.v, rv, w, key)) continue;   // dormant until a neighbour changes
        if (key > e.key) { q.push({key, e.v, ++stamp[e.v]}); continue; }
        c.collapse(e.v, w);
        ++collapses;
        after(e.v, w, key);
        // Re-score w and its ring.
        c.ring(w, rw);
        rw.push_back(w);
        for (auto x : rw) {
            ++stamp[x];
            float k;
            if (c.usable(x) && score(x, rv, k)) q.push({k, x, stamp[x]});
        }
        if (progress && collapses >= next_report) {
            progress(double(start_faces - c.alive_faces()) / double(span));
            next_report = collapses + 4096;
        }
    }
    return collapses;
}

} // namespace

DecimateStats reduce_mesh(Mesh& mesh, const ReduceOptions& opt) {
    DecimateStats st;
    st.faces_before = mesh.face_count();
    Collapser c(mesh);
    st.locked_vertices = c.locked();
    const double limit = opt.max_angle_deg * kPi / 180.0;
    const double cos_limit = std::cos(limit);
    // Candidate test and importance: theta = the largest angle between two face normals
    // around v; I = theta * sum_j |V_j - V|. A small multiple of the perimeter orders
    // the exactly flat vertices (theta = 0) shortest-edges first.
    auto score = [&](std::uint32_t v, std::vector<std::uint32_t>& ring, float& key) {
        double min_dot = 1.0;
        std::uint32_t fs[64];
        int n = 0;
        bool many = false;
        c.for_faces(v, [&](std::uint32_t f) {
            if (n < 64) fs[n++] = f; else many = true;
        });
        if (many || n < 3) return false;
        for (int i = 0; i < n; ++i)
            for (int j = i + 1; j < n; ++j)
                min_dot = std::min(min_dot, double(dot(c.normal(fs[i]), c.normal(fs[j]))));
        const double theta = std::acos(std::clamp(min_dot, -1.0, 1.0));
        if (!(theta < limit)) return false;
        c.ring(v, ring);
        double L = 0;
        const Vec3d p(c.point(v));
        for (auto x : ring) L += length(Vec3d(c.point(x)) - p);
        key = float(theta * L + 1e-4 * L);
        return true;
    };
    auto choose = [&](std::uint32_t v, const std::vector<std::uint32_t>& rv, std::uint32_t& w, float&) {
        double best = -2, best_len = HUGE_VAL;
        w = kNone;
        const Vec3d p(c.point(v));
        for (auto x : rv) {
            double mc;
            if (!c.check(v, x, rv, cos_limit, opt.max_aspect_ratio, mc)) continue;
            const double len = length(Vec3d(c.point(x)) - p);
            if (mc > best + 1e-9 || (mc > best - 1e-9 && len < best_len)) { best = mc; best_len = len; w = x; }
        }
        return w != kNone;
    };
    st.collapses = run_queue(c, mesh.positions.size(), opt.target_faces, HUGE_VALF, opt.progress, score, choose,
                             [](std::uint32_t, std::uint32_t, float) {});
    c.finish();
    st.faces_after = mesh.face_count();
    return st;
}

namespace {
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
} // namespace

DecimateStats quadric_decimate(Mesh& mesh, const QuadricOptions& opt) {
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
    Collapser c(mesh);
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
    auto choose = [&](std::uint32_t v, const std::vector<std::uint32_t>& rv, std::uint32_t& w, float& key) {
        double best = HUGE_VAL;
        w = kNone;
        for (auto x : rv) {
            const double e = cost(v, x) / area_of(v, x);
            if (e >= best) continue;
            double mc;
            if (!c.check(v, x, rv, cos_limit, opt.max_aspect_ratio, mc)) continue;
            best = e;
            w = x;
        }
        if (w == kNone) return false;
        key = std::max(key, float(best));
        return true;
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

} // namespace cm
