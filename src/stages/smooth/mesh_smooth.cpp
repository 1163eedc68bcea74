#include "mesh_smooth.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <limits>
#include <optional>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "geometry/hull_distance.h"
#include "geometry/mesh_adjacency.h"
#include "geometry/mesh_intersect.h"
#include "geometry/uninit_vector.h"

namespace cm {

namespace {

constexpr int kBisections = 8;

// std::nextafter(f, +infinity), inline (it is a library call, made once per vertex and step).
float next_up(float f) {
    if (!(f < std::numeric_limits<float>::infinity())) return f; // +infinity and NaN stay
    if (f == 0.0f) return std::numeric_limits<float>::denorm_min();
    const auto bits = std::bit_cast<std::uint32_t>(f);
    return std::bit_cast<float>(f > 0.0f ? bits + 1 : bits - 1);
}

// The views a vertex's hull distance is asked of. The hull distance is the largest of the
// views' distances, and near the hull (where the constraint binds) one view gives it while
// the others see the vertex far inside their silhouettes. A view whose distance at the
// vertex is below -tol by a margin cannot reach -tol before the vertex has moved by
// margin / lipschitz, so until then it is not asked: every answer stays the same (each test
// below is decided by the asked views whenever a skipped view could not change it, and asks
// every view otherwise), at about one view's samples per step instead of all of them.
struct AskedViews {
    const HullDistance* hull = nullptr;
    double tol = 0;
    UninitVector<HullDistance::ViewMask> mask; // per vertex: the views to ask
    UninitVector<float> slack;                 // per vertex: how far it may move before a skipped view could matter

    bool skip = true;
    std::atomic<std::size_t> skipping_steps{0};
    // Per vertex: a bound on |hull distance| where the vertex is (infinity: none). The hull
    // distance moves by at most `lip` per unit the vertex moves, so a step no longer than
    // (tol - bound) / lip keeps it within the tolerance: that step is taken whole, as asking
    // would have found, without a sample. 0 when some view's distance cannot be bounded so.
    UninitVector<float> near;
    double lip = 0;
    AskedViews(const HullDistance* h, double t, std::size_t n, bool skip_far) : hull(h), tol(t), skip(skip_far) {
        if (!h) return;
        for (std::size_t i = 0; i < h->view_count(); ++i) lip = std::max(lip, h->lipschitz(i));
        for (std::size_t i = 0; i < h->view_count() && lip > 0; ++i)
            if (!(h->lipschitz(i) > 0)) lip = 0;
        // Written first side by side (a fill in the constructors would map the pages on one thread).
        mask.resize(n);
        slack.resize(n);
        if (lip > 0) near.resize(n);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 14), [&](const auto& r) {
            for (std::size_t v = r.begin(); v != r.end(); ++v) {
                mask[v] = h->all_views();
                slack[v] = -1.0f;
                if (lip > 0) near[v] = std::numeric_limits<float>::infinity();
            }
        });
    }
    // Whether a step of length `reach` from the vertex keeps it within the tolerance for certain.
    bool surely_within(std::size_t v, double reach) const {
        return lip > 0 && double(near[v]) + lip * reach * (1 + 1e-9) <= tol * (1 - 1e-9);
    }
    // The vertex is now where |hull distance| is `d` (infinity: not known).
    void now_at(std::size_t v, double d) {
        if (lip > 0) near[v] = next_up(float(d));
    }
    // Whether the vertex's mask holds for every point within `reach` of where it is.
    bool valid(std::size_t v, double reach) const { return double(slack[v]) >= reach; }
    // The hull distance at q asked of every view; the vertex's mask is made afresh from the
    // answers, about q: the views it can move well past `reach` from q in before they matter
    // are skipped.
    double ask_all(std::size_t v, const Vec3d& q, double reach) {
        double best = -std::numeric_limits<double>::infinity(), allowance = std::numeric_limits<double>::infinity();
        HullDistance::ViewMask m = hull->all_views();
        for (std::size_t i = 0; i < hull->view_count(); ++i) {
            const double d = hull->view_distance(i, q);
            best = std::max(best, d);
            const double lip = hull->lipschitz(i);
            if (lip <= 0 || !skip) continue;
            const double room = (-d - tol) / lip; // how far from q view i stays below -tol
            if (room > 4 * reach) {
                m &= ~(HullDistance::ViewMask(1) << i);
                allowance = std::min(allowance, room);
            }
        }
        mask[v] = m;
        // No view skipped: asked afresh at the next step.
        slack[v] = m == hull->all_views() ? -1.0f : float(std::min(allowance, 1e30) * (1 - 1e-6));
        return best;
    }
    // With a valid mask, the hull distance at p: exact when it is -tol or more (every
    // skipped view is below -tol there), and asked of every view otherwise.
    double distance(std::size_t v, const Vec3d& p) const {
        const double d = hull->distance(p, mask[v]);
        return d >= -tol ? d : (*hull)(p);
    }
    // With a valid mask, whether the hull distance at p is at most `limit` (>= -tol).
    bool at_most(std::size_t v, const Vec3d& p, double limit) const { return hull->distance(p, mask[v]) <= limit; }
    // With a valid mask, HullDistance::within (exact as distance()).
    bool within(std::size_t v, const Vec3d& p, double bound, std::size_t& first) const {
        double largest;
        if (!hull->within(p, bound, first, mask[v], largest)) return false;
        return largest >= -tol ? true : hull->within(p, bound, first);
    }
    void moved(std::size_t v, double by) { slack[v] -= float(by * (1 + 1e-6)); }
};

// One Jacobi step: dst[v] = src[v] + w * (mean of src over v's neighbours - src[v]).
// With a hull, the step is shortened so that |hull distance| stays within the
// tolerance (or does not grow, for a vertex that starts outside the band).
// `free` (may be null): the vertices that only have to stay inside the hull (within tol).
std::size_t relax(const VertexAdjacency& adj, const std::vector<Vec3f>& src, std::vector<Vec3f>& dst, double w,
                  AskedViews& asked, const std::vector<char>* free) {
    const HullDistance* hull = asked.hull;
    const double tol = asked.tol;
    const std::size_t nv = src.size();
    std::atomic<std::size_t> clamped{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 2048), [&](const tbb::blocked_range<std::size_t>& r) {
        std::size_t local = 0, skipping = 0;
        constexpr std::size_t kAhead = 8; // vertices between a prefetch and its use
        for (std::size_t v = r.begin(); v != r.end(); ++v) {
            if (hull && v + kAhead < r.end()) hull->prefetch(Vec3d(src[v + kAhead]), asked.mask[v + kAhead]);
            const std::uint32_t b = adj.offsets[v], e = adj.offsets[v + 1];
            const Vec3f p = src[v];
            if (b == e) {
                dst[v] = p;
                continue;
            }
            Vec3f sum{0, 0, 0};
            for (std::uint32_t i = b; i < e; ++i) sum += src[adj.neighbours[i]];
            const Vec3f step = (sum * (1.0f / float(e - b)) - p) * float(w);
            if (!hull) {
                dst[v] = p + step;
                continue;
            }
            const Vec3d p0(p), s(step);
            const double reach = length(s);
            double lo = 1; // the part of the step taken
            // The largest part of the step (to 1/2^kBisections) whose end `keeps`, by bisection;
            // `guess` (in (0, 1), when known) is where the hull distance, taken as linear along
            // the step, leaves the band. The search asks there and one unit further first, and
            // bisects what is left between the answers: where `keeps` holds up to one point
            // along the step and not beyond (the distance is monotone over a step of a fraction
            // of a pixel, as a rule), that is bisection's answer, in two questions instead of
            // kBisections.
            auto bisect = [&](auto&& keeps, double guess = -1) {
                constexpr double unit = 1.0 / double(1 << kBisections);
                double kept = 0, refused = 1;
                if (guess > 0 && guess < 1) {
                    const double t = std::floor(guess / unit) * unit;
                    if (t > 0 && !keeps(p0 + s * t)) refused = t;
                    else {
                        kept = t;
                        (keeps(p0 + s * (t + unit)) ? kept : refused) = t + unit;
                    }
                }
                while (refused - kept > 1.5 * unit) {
                    const double mid = kept + std::floor(0.5 * (refused - kept) / unit) * unit;
                    (keeps(p0 + s * mid) ? kept : refused) = mid;
                }
                return kept;
            };
            // Where the distance h, from h0 at the start to h1 at the end, reaches the band's
            // side that h1 lies beyond.
            auto crossing = [](double h0, double h1, double bound) {
                const double target = h1 > 0 ? bound : -bound;
                return (target - h0) / (h1 - h0);
            };
            double h_end = std::numeric_limits<double>::infinity(); // |hull distance| at the end, when known
            if (asked.valid(v, reach)) {
                ++skipping;
                if (free && (*free)[v]) {
                    if (!asked.at_most(v, p0 + s, tol))
                        lo = bisect([&](const Vec3d& x) { return asked.at_most(v, x, tol); });
                } else if (asked.surely_within(v, reach)) {
                    h_end = double(asked.near[v]) + asked.lip * reach * (1 + 1e-9);
                } else if (const double h1 = asked.distance(v, p0 + s); std::fabs(h1) > tol) {
                    const double h0 = asked.distance(v, p0), bound = std::max(tol, std::fabs(h0));
                    std::size_t first = 0; // the view that refused the last point
                    if (std::fabs(h1) > bound)
                        lo = bisect([&](const Vec3d& x) { return asked.within(v, x, bound, first); },
                                    crossing(h0, h1, bound));
                    else h_end = std::fabs(h1);
                } else {
                    h_end = std::fabs(h1);
                }
                asked.moved(v, reach * lo);
            } else {
                // Every view asked at the end of the step, and the mask made afresh there.
                const double h1 = asked.ask_all(v, p0 + s, reach);
                if (free && (*free)[v]) {
                    if (h1 > tol) lo = bisect([&](const Vec3d& x) { return (*hull)(x) <= tol; });
                } else if (std::fabs(h1) > tol) {
                    const double h0 = (*hull)(p0), bound = std::max(tol, std::fabs(h0));
                    std::size_t first = 0;
                    if (std::fabs(h1) > bound)
                        lo = bisect([&](const Vec3d& x) { return hull->within(x, bound, first); },
                                    crossing(h0, h1, bound));
                }
                if (lo == 1) h_end = std::fabs(h1);
                asked.moved(v, reach * (1 - lo)); // the mask is about p0 + s
            }
            asked.now_at(v, lo == 1 ? h_end : std::numeric_limits<double>::infinity());
            if (lo == 1) {
                dst[v] = p + step;
                continue;
            }
            dst[v] = p + step * float(lo);
            ++local;
        }
        clamped += local;
        if (hull) asked.skipping_steps += skipping;
    });
    return clamped.load();
}

// Faces that turned over against their input normal or lost (almost) all their area.
void find_bad_shapes(const Mesh& in, const std::vector<Vec3f>& p, const std::vector<std::uint32_t>* only,
                     std::vector<std::uint32_t>& out) {
    const std::size_t n = only ? only->size() : in.triangles.size();
    tbb::enumerable_thread_specific<std::vector<std::uint32_t>> found;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        auto& local = found.local();
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            const std::uint32_t f = only ? (*only)[i] : std::uint32_t(i);
            const auto& t = in.triangles[f];
            const Vec3d a(p[t[0]]), b(p[t[1]]), c(p[t[2]]);
            const Vec3d a0(in.positions[t[0]]), b0(in.positions[t[1]]), c0(in.positions[t[2]]);
            const Vec3d n = cross(b - a, c - a), n0 = cross(b0 - a0, c0 - a0);
            const double len = length(n), len0 = length(n0);
            // Collapsed: area below 1e-6 of the face's input area (MC faces can be small).
            if (len <= 1e-6 * len0 || dot(n, n0) <= 0) local.push_back(f);
        }
    });
    for (auto& v : found) out.insert(out.end(), v.begin(), v.end());
}

// Two vertices closer than this fraction of the bounding-box diagonal count as drawn onto
// one another: ten times the output check's kCoincidentTolerance, so what the guard leaves
// apart stays apart in `conceptmesh check` and in an importer's merge by distance.
constexpr double kSeparation = 10 * kCoincidentTolerance;

// The guard of SmoothOptions::guard: pulls the vertices of bad faces back towards the
// input positions until no face crosses another, turns over or collapses, and no two
// vertices that were apart in the input coincide. The umbrella operator (factor 1) draws
// two vertices with the same ring of neighbours (the two tips of a thin part, one cell
// across) onto the ring's centroid: an importer welds them and the mesh is pinched there.
//
// The first check covers every face at the smoothed positions, with an index of the faces
// there (one pose: smaller boxes, fewer entries than an index of everything between input and
// smoothed). The faces around vertices pulled back are then at blends of the two, which
// that index does not hold: they go into a second, small index covering both poses, and a
// face checked in a later round is asked of both.
void guard_surface(const Mesh& in, std::vector<Vec3f>& p, SmoothStats& st) {
    const std::vector<Vec3f> smoothed = p;
    // The fans that lie over a plane one-to-one: pairs of their faces need no crossing test
    // (nine in ten of the pairs the index finds on a smooth surface).
    const std::vector<char> fans = embedded_fans(in.triangles, smoothed);
    const SelfIntersectionIndex index(in.triangles, smoothed);
    Vec3f lo, hi;
    in.bounds(lo, hi);
    const double separation = kSeparation * length(Vec3d(hi) - Vec3d(lo));
    // Vertices the input already has together are left alone (they are the input's own).
    // Asked only about vertices together at p (few, often none), in one pass over the input
    // per batch of new questions: an index of the asked vertices' input positions, which each
    // input vertex looks itself up in (no index of the whole input beside the one of p).
    // 0: not asked yet, 1: together in the input, 2: apart.
    std::vector<char> input_answer(p.size(), 0);
    auto ask_input = [&](const std::vector<std::uint32_t>& vs) {
        std::vector<std::uint32_t> asked;
        std::vector<Vec3f> where;
        for (auto v : vs)
            if (!input_answer[v]) {
                asked.push_back(v);
                where.push_back(in.positions[v]);
            }
        if (asked.empty()) return;
        const CoincidenceIndex index_of_asked(where, separation);
        // A coarse grid over the input's box marks the cells within twice the separation of an
        // asked vertex: only the input vertices in marked cells can be near one, and only they
        // look themselves up (the same answers, for a bit test per vertex elsewhere).
        constexpr int kGrid = 128;
        const Vec3d origin(lo), span = vmax(Vec3d(hi) - origin, Vec3d(1e-30, 1e-30, 1e-30));
        const Vec3d per(kGrid / span.x, kGrid / span.y, kGrid / span.z);
        auto cell_of = [&](double x, int a) {
            const double t = (x - origin[a]) * per[a];
            return t >= 0 ? int(std::min(t, double(kGrid - 1))) : 0; // NaN to 0 (near nothing anyway)
        };
        std::vector<char> marked_cells(std::size_t(kGrid) * kGrid * kGrid, 0);
        for (const Vec3f& q : where) {
            int c0[3], c1[3];
            for (int a = 0; a < 3; ++a) {
                c0[a] = cell_of(double(q[a]) - 2 * separation, a);
                c1[a] = cell_of(double(q[a]) + 2 * separation, a);
            }
            for (int z = c0[2]; z <= c1[2]; ++z)
                for (int y = c0[1]; y <= c1[1]; ++y)
                    for (int x = c0[0]; x <= c1[0]; ++x)
                        marked_cells[(std::size_t(z) * kGrid + std::size_t(y)) * kGrid + std::size_t(x)] = 1;
        }
        std::vector<char> hit(asked.size(), 0);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, in.positions.size(), 1 << 14), [&](const auto& r) {
            for (std::size_t w = r.begin(); w != r.end(); ++w) {
                const Vec3f& q = in.positions[w];
                const std::size_t cell = (std::size_t(cell_of(q.z, 2)) * kGrid + std::size_t(cell_of(q.y, 1))) * kGrid +
                                         std::size_t(cell_of(q.x, 0));
                if (!marked_cells[cell]) continue;
                index_of_asked.near_point(q, [&](std::uint32_t k) {
                    if (asked[k] != w) std::atomic_ref<char>(hit[k]).store(1, std::memory_order_relaxed);
                });
            }
        });
        for (std::size_t k = 0; k < asked.size(); ++k) input_answer[asked[k]] = hit[k] ? 1 : 2;
    };
    // Vertices within the separation of another at p, kept up to date as vertices move: a
    // vertex's answer changes only when it or a vertex near it (before or after) moves.
    CoincidenceIndex coincidence(p, separation);
    std::vector<std::uint32_t> together = coincidence.all(), recheck;
    std::vector<std::uint32_t> bad, badv; // faces, and vertices drawn onto another
    auto collect = [&](const std::vector<FacePair>& pairs, const std::vector<std::uint32_t>* only) {
        bad.clear();
        for (const auto& pr : pairs) {
            bad.push_back(pr[0]);
            bad.push_back(pr[1]);
        }
        find_bad_shapes(in, p, only, bad);
        std::sort(bad.begin(), bad.end());
        bad.erase(std::unique(bad.begin(), bad.end()), bad.end());
        badv.clear();
        ask_input(together);
        for (auto v : together)
            if (input_answer[v] == 2) badv.push_back(v);
        ++st.guard_rounds;
    };
    collect(index.all(p, {}, &fans), nullptr);
    st.bad_faces = bad.size();
    st.coincident = badv.size();
    if (bad.empty() && badv.empty()) return; // the common case: nothing more to build

    std::vector<float> weight(p.size(), 1.0f); // position = input + weight * (smoothed - input)
    // Faces to re-check, vertices moved this round, and the faces the index holds at a moved
    // vertex's smoothed position (those around the vertex among them: no table of the faces
    // around every vertex is built for the few that move).
    std::vector<std::uint32_t> check, moved, near_faces;
    // The faces that ever had a vertex pulled back (their triangles, and their faces in `in`).
    std::vector<char> face_moved(in.triangles.size(), 0);
    std::vector<std::array<std::uint32_t, 3>> moving_tris;
    std::vector<std::uint32_t> moving_faces;
    auto swept = [&](std::uint32_t f) { // the box of every blend of the face's two poses
        const auto& t = in.triangles[f];
        SelfIntersectionIndex::Box b{in.positions[t[0]], in.positions[t[0]]};
        for (const auto* pose : {&in.positions, &smoothed})
            for (auto v : t) b = {vmin(b.lo, (*pose)[v]), vmax(b.hi, (*pose)[v])};
        return b;
    };
    auto box_now = [&](std::uint32_t f) {
        const auto& t = in.triangles[f];
        return SelfIntersectionIndex::Box{vmin(p[t[0]], vmin(p[t[1]], p[t[2]])), vmax(p[t[0]], vmax(p[t[1]], p[t[2]]))};
    };
    auto meet = [](const SelfIntersectionIndex::Box& a, const SelfIntersectionIndex::Box& b) {
        return !(a.lo.x > b.hi.x || b.lo.x > a.hi.x || a.lo.y > b.hi.y || b.lo.y > a.hi.y || a.lo.z > b.hi.z ||
                 b.lo.z > a.hi.z);
    };
    // The crossing pairs at p with a face in `faces`: the other face is in `index` at its
    // smoothed position, or among the moving faces.
    auto crossings_of = [&](const std::vector<std::uint32_t>& faces, const SelfIntersectionIndex& moving) {
        tbb::enumerable_thread_specific<std::vector<FacePair>> found;
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, faces.size(), 64), [&](const auto& r) {
            auto& local = found.local();
            std::vector<std::uint32_t> near, more;
            for (std::size_t i = r.begin(); i != r.end(); ++i) {
                const std::uint32_t fa = faces[i];
                const SelfIntersectionIndex::Box reach = swept(fa), now = box_now(fa);
                index.candidates(reach, near);
                moving.candidates(reach, more);
                for (auto& k : more) k = moving_faces[k];
                near.insert(near.end(), more.begin(), more.end());
                std::sort(near.begin(), near.end());
                near.erase(std::unique(near.begin(), near.end()), near.end());
                for (std::uint32_t fb : near)
                    if (fb != fa && meet(now, box_now(fb)) && triangles_cross(p, in.triangles[fa], in.triangles[fb]))
                        local.push_back({std::min(fa, fb), std::max(fa, fb)});
            }
        });
        std::vector<FacePair> pairs;
        for (auto& v : found) pairs.insert(pairs.end(), v.begin(), v.end());
        std::sort(pairs.begin(), pairs.end());
        pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
        return pairs;
    };
    std::vector<char> marked(p.size(), 0);
    while (!bad.empty() || !badv.empty()) {
        moved.clear();
        auto pull_back = [&](std::uint32_t v) {
            if (marked[v] || weight[v] == 0.0f) return;
            marked[v] = 1;
            moved.push_back(v);
            weight[v] = weight[v] > 0.3f ? weight[v] * 0.5f : 0.0f;
            p[v] = in.positions[v] + (smoothed[v] - in.positions[v]) * weight[v];
        };
        for (auto f : bad)
            for (auto v : in.triangles[f]) pull_back(v);
        for (auto v : badv) pull_back(v);
        if (moved.empty()) {
            st.unresolved = bad.size();
            break;
        } // the input's own faces
        st.pulled_back += moved.size();
        recheck = together; // those together before, those moved and those they now meet
        for (auto v : moved) coincidence.moved(v);
        for (auto v : moved) {
            recheck.push_back(v);
            coincidence.near(v, [&](std::uint32_t w) { recheck.push_back(w); });
        }
        std::sort(recheck.begin(), recheck.end());
        recheck.erase(std::unique(recheck.begin(), recheck.end()), recheck.end());
        together.clear();
        for (auto v : recheck)
            if (coincidence.has_near(v)) together.push_back(v);
        check.clear();
        for (auto v : moved) {
            marked[v] = 0;
            index.faces_near(smoothed[v], near_faces);
            for (auto f : near_faces) {
                const auto& t = in.triangles[f];
                if (t[0] == v || t[1] == v || t[2] == v) check.push_back(f);
            }
        }
        std::sort(check.begin(), check.end());
        check.erase(std::unique(check.begin(), check.end()), check.end());
        for (auto f : check)
            if (!face_moved[f]) {
                face_moved[f] = 1;
                moving_tris.push_back(in.triangles[f]);
                moving_faces.push_back(f);
            }
        const SelfIntersectionIndex moving(moving_tris, in.positions, &smoothed);
        collect(crossings_of(check, moving), &check);
    }
}

// The smoothing of `in`'s positions: `a` holds them on entry and the result on return.
SmoothStats smooth_positions(const Mesh& in, std::vector<Vec3f>& a, const SmoothOptions& opt) {
    SmoothStats stats;
    std::vector<char> used(a.size(), 0); // vertices with neighbours (on a face)
    {
        // The adjacency and the second buffer are let go before the guard, the largest user
        // of memory, builds its indices.
        const VertexAdjacency adj = build_vertex_adjacency(in);
        std::vector<Vec3f> b(a.size());
        const double tol = opt.tolerance;
        AskedViews asked(opt.hull, tol, a.size(), opt.skip_far_views);
        // Vertices that start inside the hull, farther than the tolerance, move freely inside it.
        std::vector<char> free_inside;
        if (opt.hull && opt.inside_free) {
            free_inside.resize(a.size());
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, a.size(), 2048), [&](const auto& r) {
                for (std::size_t v = r.begin(); v != r.end(); ++v) free_inside[v] = (*opt.hull)(Vec3d(a[v])) < -tol;
            });
        }
        const std::vector<char>* free = free_inside.empty() ? nullptr : &free_inside;
        for (int it = 0; it < opt.iterations; ++it) {
            if (opt.method == SmoothOptions::Method::Laplacian) {
                stats.clamped_steps += relax(adj, a, b, opt.factor, asked, free);
                a.swap(b);
            } else {
                stats.clamped_steps += relax(adj, a, b, opt.lambda, asked, free);
                stats.clamped_steps += relax(adj, b, a, opt.mu, asked, free);
            }
            if (opt.progress) opt.progress(double(it + 1) / opt.iterations);
        }
        for (std::size_t v = 0; v < used.size(); ++v) used[v] = adj.degree(std::uint32_t(v)) > 0;
        stats.skipping_steps = asked.skipping_steps.load();
    }
    if (opt.guard) guard_surface(in, a, stats);
    if (opt.hull) {
        stats.max_hull_distance = tbb::parallel_reduce(
            tbb::blocked_range<std::size_t>(0, a.size(), 4096), 0.0,
            [&](const tbb::blocked_range<std::size_t>& r, double m) {
                for (std::size_t v = r.begin(); v != r.end(); ++v)
                    if (used[v]) m = std::max(m, std::fabs((*opt.hull)(Vec3d(a[v]))));
                return m;
            },
            [](double x, double y) { return std::max(x, y); });
    }
    return stats;
}

} // namespace

SmoothStats smooth_mesh(Mesh& mesh, const SmoothOptions& opt) {
    if (mesh.positions.empty() || opt.iterations <= 0) return {};
    std::vector<Vec3f> a = mesh.positions;
    const SmoothStats stats = smooth_positions(mesh, a, opt);
    mesh.positions = std::move(a);
    if (!mesh.normals.empty()) mesh.compute_normals();
    return stats;
}

SmoothStats smooth_mesh(const Mesh& in, Mesh& out, const SmoothOptions& opt) {
    if (in.positions.empty() || opt.iterations <= 0) {
        out = in;
        return {};
    }
    std::vector<Vec3f> a = in.positions;
    const SmoothStats stats = smooth_positions(in, a, opt);
    out.positions = std::move(a);
    out.triangles = in.triangles;
    out.uvs = in.uvs;
    out.colors = in.colors;
    out.corner_uvs = in.corner_uvs;
    out.texture = in.texture;
    out.normals.clear();
    if (!in.normals.empty()) out.compute_normals();
    return stats;
}

} // namespace cm
