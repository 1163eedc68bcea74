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

#include "core/error.h"
#include "geometry/hull_distance.h"
#include "geometry/mesh_adjacency.h"
#include "smooth_creases.h"
#include "smooth_guard.h"
#include "util/uninit_vector.h"

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
    // Per vertex: a bound on |hull distance| where the vertex is (infinity: none); for a
    // vertex free inside the hull, a bound on its signed hull distance, which only has to
    // stay below the tolerance. The hull
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
    // With a valid mask, the largest distance of the asked views at p (the hull distance when
    // it is -tol or more; below -tol otherwise).
    double masked(std::size_t v, const Vec3d& p) const { return hull->distance(p, mask[v]); }
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
// `plane` (may be null): per vertex, the normal of the plane its step is kept in (zero: free).
std::size_t relax(const VertexAdjacency& adj, const std::vector<Vec3f>& src, std::vector<Vec3f>& dst, double w,
                  AskedViews& asked, const std::vector<char>* free, const std::vector<Vec3f>* plane) {
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
            Vec3f step = (sum * (1.0f / float(e - b)) - p) * float(w);
            if (plane) {
                const Vec3f n = (*plane)[v];
                step -= n * dot(step, n);
            }
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
            const bool is_free = free && (*free)[v];
            if (asked.surely_within(v, reach) && (is_free || asked.valid(v, reach))) {
                // The hull distance is bounded far enough within the tolerance: the step is
                // taken whole without a sample (the bound moves with it). A free vertex's bound
                // holds without the mask, which only has to stay below the tolerance.
                h_end = double(asked.near[v]) + asked.lip * reach * (1 + 1e-9);
                if (asked.valid(v, reach)) {
                    ++skipping;
                    asked.moved(v, reach);
                }
            } else if (asked.valid(v, reach)) {
                ++skipping;
                if (is_free) {
                    const double d = asked.masked(v, p0 + s);
                    if (d <= tol) h_end = std::max(d, -tol); // the skipped views lie below -tol
                    else lo = bisect([&](const Vec3d& x) { return asked.at_most(v, x, tol); });
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
                if (is_free) {
                    if (h1 > tol) lo = bisect([&](const Vec3d& x) { return (*hull)(x) <= tol; });
                } else if (std::fabs(h1) > tol) {
                    const double h0 = (*hull)(p0), bound = std::max(tol, std::fabs(h0));
                    std::size_t first = 0;
                    if (std::fabs(h1) > bound)
                        lo = bisect([&](const Vec3d& x) { return hull->within(x, bound, first); },
                                    crossing(h0, h1, bound));
                }
                if (lo == 1) h_end = is_free ? h1 : std::fabs(h1);
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

// The enclosed volume (the divergence theorem over the faces), for the volume_change_pct
// metric: one parallel pass, where a full check_mesh (edges sorted, fans per vertex)
// cost more than the smoothing itself on a million faces. Deterministic reduce: the sum is
// added up in one order whatever the thread count, so reports are byte-identical.
double signed_volume(const Mesh& m) {
    return tbb::parallel_deterministic_reduce(
               tbb::blocked_range<std::size_t>(0, m.triangles.size(), 1 << 14), 0.0,
               [&](const tbb::blocked_range<std::size_t>& r, double acc) {
                   for (std::size_t f = r.begin(); f != r.end(); ++f) {
                       const auto& t = m.triangles[f];
                       acc += dot(Vec3d(m.positions[t[0]]), cross(Vec3d(m.positions[t[1]]), Vec3d(m.positions[t[2]])));
                   }
                   return acc;
               },
               [](double a, double b) { return a + b; }) /
           6.0;
}

// The hull `opt.constrain` asks for (null for none); throws when it needs one and has none.
const HullDistance* constraining_hull(const SmoothOptions& opt, const HullDistance* hull) {
    if (opt.constrain == SmoothOptions::Constrain::None) return nullptr;
    if (!hull)
        throw Error(std::string("constrain: ") + (opt.constrain == SmoothOptions::Constrain::Hull ? "hull" : "inside") +
                    " needs the views input (inputs: { mesh: ..., views: <views node> })");
    return hull;
}

// The smoothing of `in`'s positions: `a` holds them on entry and the result on return.
SmoothStats smooth_positions(const Mesh& in, std::vector<Vec3f>& a, const SmoothOptions& opt, const HullDistance* hull,
                             const Progress& progress) {
    SmoothStats stats;
    std::vector<char> used(a.size(), 0); // vertices with neighbours (on a face)
    const double tol = hull ? opt.tolerance_px * hull->finest_pixel() : 0.0;
    {
        // The adjacency and the second buffer are let go before the guard, the largest user
        // of memory, builds its indices.
        const VertexAdjacency ring = build_vertex_adjacency(in);
        std::optional<CreaseHold> hold;
        if (opt.crease_angle_deg > 0) {
            hold.emplace(hold_creases(in, ring, opt.crease_angle_deg, opt.crease_reach, opt.crease_views));
            stats.creases = true;
            stats.crease_vertices = hold->crease_vertices;
            stats.crease_held = hold->held_vertices;
            stats.short_creases = hold->short_creases;
        }
        const VertexAdjacency& adj = hold ? hold->adj : ring;
        const std::vector<Vec3f>* plane = hold ? &hold->plane : nullptr;
        std::vector<Vec3f> b(a.size());
        AskedViews asked(hull, tol, a.size(), opt.skip_far_views);
        // Vertices that start inside the hull, farther than the tolerance, move freely inside it.
        std::vector<char> free_inside;
        if (hull && opt.constrain == SmoothOptions::Constrain::Inside) {
            free_inside.resize(a.size());
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, a.size(), 2048), [&](const auto& r) {
                for (std::size_t v = r.begin(); v != r.end(); ++v) free_inside[v] = (*hull)(Vec3d(a[v])) < -tol;
            });
        }
        const std::vector<char>* free = free_inside.empty() ? nullptr : &free_inside;
        for (int it = 0; it < opt.iterations; ++it) {
            if (opt.method == SmoothOptions::Method::Laplacian) {
                stats.clamped_steps += relax(adj, a, b, opt.factor, asked, free, plane);
                a.swap(b);
            } else {
                stats.clamped_steps += relax(adj, a, b, opt.lambda, asked, free, plane);
                stats.clamped_steps += relax(adj, b, a, opt.mu, asked, free, plane);
            }
            progress(double(it + 1) / opt.iterations);
        }
        for (std::size_t v = 0; v < used.size(); ++v) used[v] = ring.degree(std::uint32_t(v)) > 0;
        stats.skipping_steps = asked.skipping_steps.load();
    }
    if (opt.guard) guard_surface(in, a, stats);
    if (hull) {
        stats.max_hull_distance = tbb::parallel_reduce(
            tbb::blocked_range<std::size_t>(0, a.size(), 4096), 0.0,
            [&](const tbb::blocked_range<std::size_t>& r, double m) {
                for (std::size_t v = r.begin(); v != r.end(); ++v)
                    if (used[v]) m = std::max(m, std::fabs((*hull)(Vec3d(a[v]))));
                return m;
            },
            [](double x, double y) { return std::max(x, y); });
    }
    return stats;
}

} // namespace

void SmoothOptions::declare_common(ParamBinder& b) {
    b.add(iterations, ParamSpec::Int("iterations", 10, 0, 10000, "",
                                     "smoothing iterations (Taubin: one lambda step and one mu step each)"));
    b.add(constrain,
          ParamSpec::Enum("constrain", "none", {"none", "hull", "inside"},
                          "hull: keep every vertex within `tolerance` of the visual hull of the views "
                          "(needs the views input), so the drawn outline is kept; inside: the vertices on "
                          "the hull stay on it, the others move freely inside it (a surface carved inside "
                          "the hull: hull.plausible)"),
          {Constrain::None, Constrain::Hull, Constrain::Inside});
    b.add(tolerance_px, ParamSpec::Float("tolerance", 0.5, 0.0, 100.0, "px",
                                         "hull constraint: largest distance of a vertex from the hull, in pixels of "
                                         "the finest view"));
    b.add(guard, ParamSpec::Bool("guard", true,
                                 "keep the surface valid: vertices of faces that would cross another face, turn "
                                 "over or collapse, and vertices drawn onto another vertex, are moved back towards "
                                 "their input positions"));
    b.add(crease_angle_deg,
          ParamSpec::Float("creases", 0.0, 0.0, 180.0, "deg",
                           "hold sharp creases: a vertex on an edge whose two faces meet at more than this "
                           "smooths along its crease only (and stays where creases end or meet), a vertex "
                           "beside one stays in its plane; 0: off, as in the paper"));
    b.add(crease_reach,
          ParamSpec::Float("crease_reach", 0.0, 0.0, 1e6, "edges",
                           "with creases: hold only a crease (connected sharp edges) whose box reaches at least "
                           "this many mean edge lengths, and the edges of shorter ones along an orthographic "
                           "view's direction; other short ones (the steps of a hull carved from many cameras) "
                           "are smoothed; 0: every crease"));
    b.add(hard_surface,
          ParamSpec::Bool("hard_surface", false,
                          "with creases: on a machined part (every drawing's outline mostly straight, the test of "
                          "hull.plausible's hard_surface, which then keeps the hull) hold no crease, as in the paper: "
                          "the hull's creases are where two drawings' outlines meet, and the smoothing cuts them "
                          "within `tolerance`; needs the views input"));
}

void SmoothOptions::declare_laplacian(ParamBinder& b) {
    b.add(factor, ParamSpec::Float("factor", 1.0, 0.0, 1.0, "",
                                   "fraction of the umbrella step taken per iteration (1: the paper's operator)"));
}

void SmoothOptions::declare_taubin(ParamBinder& b) {
    b.add(lambda, ParamSpec::Float("lambda", 0.63, 0.0, 1.0, "", "shrinking step, in (0, 1)"));
    b.add(mu, ParamSpec::Float("mu", -0.67, -1.0, 0.0, "", "inflating step, in (-1, 0) with |mu| > lambda"));
}

void SmoothStats::report(Metrics& m) const {
    m.count("vertices", vertices);
    m.count("faces", faces);
    m.metric("volume_before", volume_before);
    m.metric("volume_after", volume_after);
    if (volume_before != 0) m.metric("volume_change_pct", 100.0 * (volume_after - volume_before) / volume_before);
    if (guarded) {
        m.count("guard_bad_faces", bad_faces);
        m.count("guard_coincident", coincident);
        m.count("guard_pulled_back", pulled_back);
        m.count("guard_rounds", guard_rounds);
        if (unresolved)
            m.warn(std::to_string(unresolved) +
                   " faces of the input cross another face, turn over or collapse; smoothing left them as they were");
    }
    if (creases) {
        m.count("crease_vertices", crease_vertices);
        m.count("crease_held", crease_held);
        m.count("short_creases", short_creases);
    }
    if (constrained) {
        m.count("clamped_steps", clamped_steps);
        m.metric("max_hull_distance_px", max_hull_distance / finest_pixel);
    }
}

Result<Mesh, SmoothStats> smooth_mesh(const Mesh& in, const SmoothOptions& opt, const HullDistance* hull,
                                      Progress progress) {
    hull = constraining_hull(opt, hull);
    Result<Mesh, SmoothStats> r;
    Mesh& out = r.value;
    if (in.positions.empty() || opt.iterations <= 0) {
        out = in;
    } else {
        std::vector<Vec3f> a = in.positions;
        r.stats = smooth_positions(in, a, opt, hull, progress);
        out.positions = std::move(a);
        out.triangles = in.triangles;
        out.uvs = in.uvs;
        out.colors = in.colors;
        out.corner_uvs = in.corner_uvs;
        out.texture = in.texture;
        out.normals.clear();
        if (!in.normals.empty()) out.compute_normals();
    }
    r.stats.guarded = opt.guard;
    r.stats.constrained = hull != nullptr;
    r.stats.finest_pixel = hull ? hull->finest_pixel() : 0.0;
    r.stats.vertices = out.vertex_count();
    r.stats.faces = out.face_count();
    r.stats.volume_before = signed_volume(in);
    r.stats.volume_after = signed_volume(out);
    return r;
}

SmoothStats smooth_mesh_in_place(Mesh& mesh, const SmoothOptions& opt, const HullDistance* hull, Progress progress) {
    hull = constraining_hull(opt, hull);
    if (mesh.positions.empty() || opt.iterations <= 0) return {};
    std::vector<Vec3f> a = mesh.positions;
    const SmoothStats stats = smooth_positions(mesh, a, opt, hull, progress);
    mesh.positions = std::move(a);
    if (!mesh.normals.empty()) mesh.compute_normals();
    return stats;
}

} // namespace cm
