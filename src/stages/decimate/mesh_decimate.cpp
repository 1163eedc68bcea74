#include "mesh_decimate.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "geometry/mesh_intersect.h"
#include "mesh_decimate_internal.h"
#include "outline_guard.h"

namespace cm {

namespace decimate {

// A collapse along a crease makes long faces beside it: no thinner than this (the quadric
// decimation's default), or where two sides of a thin part lie close, long faces of one
// cross the other.
constexpr double kCreaseAspect = 20.0;

// True when collapsing v into w gives each of v's changed faces a normal within acos(cos_keep)
// of one of the normals v's faces had (`old`, old_faces(v)): the faces keep their planes.
bool keeps_planes(const Collapser& c, std::uint32_t v, std::uint32_t w, double cos_keep,
                  const std::vector<Collapser::OldFace>& old) {
    const Vec3d pw(c.point(w));
    bool ok = true;
    c.for_faces(v, [&](std::uint32_t f) {
        const auto& t = c.tri(f);
        if (!ok || t[0] == w || t[1] == w || t[2] == w) return;
        Vec3d q[3];
        for (int i = 0; i < 3; ++i) q[i] = t[i] == v ? pw : Vec3d(c.point(t[i]));
        const Vec3d n = cross_of(q[0], q[1], q[2]);
        const double len = length(n);
        bool near = false;
        for (const auto& o : old)
            if (dot(n, o.n) >= cos_keep * len * o.len) {
                near = true;
                break;
            }
        ok = near;
    });
    return ok;
}

std::size_t reduce_queue(Collapser& c, std::size_t nv, const ReduceOptions& opt, std::size_t target_faces,
                         float stop_key, const Progress& progress, StartScores* start, bool sweep) {
    const double limit = opt.max_angle_deg * kPi / 180.0;
    const double cos_limit = std::cos(limit);
    const double straight = opt.crease_straightness_deg * kPi / 180.0;
    const double cos_keep = std::cos(opt.keep_planes_deg * kPi / 180.0);
    auto score = [&](std::uint32_t v, std::vector<std::uint32_t>&, float& key) {
        return importance(c, v, limit, straight, key);
    };
    // The target: among the neighbours whose collapse passes the geometric guards, the one
    // that turns the faces least (then the nearest); topology (and the outline guard, when
    // given) is checked in that order.
    struct Option {
        double cos, len;
        std::uint32_t w;
    };
    std::vector<Option> options;
    std::vector<Collapser::OldFace> old; // v's faces before the collapse, the same for every target
    std::optional<OutlineGuard::Samples> samples;
    if (opt.outline) samples.emplace(nv, opt.outline->view_count());
    constexpr double kTie = 1e-9; // cosines closer than this are a tie, which the nearer target wins
    auto before = [](const Option& a, const Option& b) {
        if (std::fabs(a.cos - b.cos) > kTie) return a.cos > b.cos;
        return a.len < b.len;
    };
    auto passes = [&](std::uint32_t v, std::uint32_t x, const std::vector<std::uint32_t>& rv) {
        return c.topology_ok(v, x, rv) && (!(opt.keep_planes_deg > 0) || keeps_planes(c, v, x, cos_keep, old)) &&
               (!opt.outline || opt.outline->keeps(c, v, x, &*samples));
    };
    std::vector<std::uint32_t> along; // a crease vertex's two targets along its crease
    auto choose = [&](std::uint32_t v, const std::vector<std::uint32_t>& ring, std::uint32_t& w, float&) {
        // A vertex in the middle of a straight crease goes along it only (into either end of
        // its crease edges): into any other neighbour it would bend the crease.
        Crease crease;
        const bool on_crease = straight_crease(c, v, limit, straight, crease);
        if (on_crease) along.assign({crease.a, crease.b});
        const std::vector<std::uint32_t>& targets = on_crease ? along : ring;
        const double aspect = !on_crease                 ? opt.max_aspect_ratio
                              : opt.max_aspect_ratio > 0 ? std::min(opt.max_aspect_ratio, kCreaseAspect)
                                                         : kCreaseAspect;
        const Vec3d p(c.point(v));
        c.old_faces(v, old);
        // The best target first, on its own: a target whose faces turn more than the best
        // found so far is given up at the first face that shows it. Most of the time the
        // best passes the topology and the outline guard, and it is the one taken.
        Option best{-2.0, 0.0, kNone};
        for (auto x : targets) {
            double mc;
            if (!c.usable(x) ||
                !c.geometry_ok(v, x, cos_limit, aspect, mc, old, best.w == kNone ? -2.0 : best.cos - kTie))
                continue;
            const Option o{mc, length(Vec3d(c.point(x)) - p), x};
            if (best.w == kNone || before(o, best)) best = o;
        }
        if (best.w == kNone) return false;
        if (passes(v, best.w, ring)) {
            w = best.w;
            return true;
        }
        // Otherwise every other valid target, in order.
        options.clear();
        for (auto x : targets) {
            double mc;
            if (x == best.w || !c.usable(x) || !c.geometry_ok(v, x, cos_limit, aspect, mc, old)) continue;
            options.push_back({mc, length(Vec3d(c.point(x)) - p), x});
        }
        std::sort(options.begin(), options.end(), before);
        for (const auto& o : options)
            if (passes(v, o.w, ring)) {
                w = o.w;
                return true;
            }
        return false;
    };
    if (sweep && start) return run_sweep(c, *start, stop_key, score, choose);
    return run_queue(
        c, nv, target_faces, stop_key, progress, score, choose, [](std::uint32_t, std::uint32_t, float) {}, start);
}

DecimateStats reduce_once(Mesh& mesh, const ReduceOptions& opt, const std::vector<char>* frozen,
                          const Progress& progress) {
    DecimateStats st;
    st.faces_before = mesh.face_count();
    Collapser c(mesh, frozen);
    st.locked_vertices = c.locked();
    st.collapses = reduce_queue(c, mesh.positions.size(), opt, opt.target_faces, HUGE_VALF, progress);
    c.finish();
    st.faces_after = mesh.face_count();
    return st;
}

} // namespace decimate

namespace {

// Runs `once` (from the input into `mesh`) and, while the result has faces crossing each
// other, runs it again from the input with the input vertices frozen where those faces
// cross (the overlap of the two faces' boxes, grown by a quarter). Frozen regions only grow
// and stay as the input had them; a restart that removes no crossing (the crossing faces
// reach beyond the frozen region) doubles the growth of the next. At most kMaxRestarts
// restarts.
template <typename Once>
auto without_crossings(const Mesh& input, Mesh& mesh, bool enabled, Once&& once) {
    if (!enabled) return once(input, mesh, nullptr);
    constexpr std::size_t kMaxRestarts = 6;
    std::vector<char> frozen;
    std::size_t last = SIZE_MAX;
    float reach = 0.25f;
    for (std::size_t restart = 0;; ++restart) {
        auto st = once(input, mesh, restart ? &frozen : nullptr);
        const std::vector<FacePair> pairs = find_self_intersections(mesh);
        st.restarts = restart;
        st.crossings_left = pairs.size();
        st.frozen_vertices = std::size_t(std::count(frozen.begin(), frozen.end(), char(1)));
        if (pairs.empty() || restart == kMaxRestarts) return st;
        if (pairs.size() >= last) reach *= 2;
        last = std::min(last, pairs.size());
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
            const float grow = reach * std::max(length(hi - lo), 0.25f * small);
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
    }
}

// `guard`: keep the result free of crossing faces (DecimateStats::restarts).
ParamSpec crossing_guard_param() {
    return ParamSpec::Bool("guard", true,
                           "keep the result free of self-intersections: where faces of nearby parts end up "
                           "crossing, reduce again from the input with the vertices there kept");
}

} // namespace

Result<Mesh, DecimateStats> reduce_mesh(const Mesh& input, const ReduceOptions& opt, Progress progress) {
    Result<Mesh, DecimateStats> r;
    r.stats = without_crossings(input, r.value, opt.no_crossings,
                                [&](const Mesh& in, Mesh& m, const std::vector<char>* frozen) {
                                    return decimate::reduce_blocked(in, m, opt, frozen, progress);
                                });
    r.stats.vertices = r.value.vertex_count();
    return r;
}

DecimateStats reduce_mesh_in_place(Mesh& mesh, const ReduceOptions& opt, Progress progress) {
    return replace_in_place(mesh, [&](const Mesh& input) { return reduce_mesh(input, opt, progress); });
}

Result<Mesh, QuadricStats> quadric_decimate(const Mesh& input, const QuadricOptions& opt, Progress progress) {
    Result<Mesh, QuadricStats> r;
    r.stats = without_crossings(input, r.value, opt.no_crossings,
                                [&](const Mesh& in, Mesh& m, const std::vector<char>* frozen) {
                                    m = in;
                                    return decimate::quadric_once(m, opt, frozen, progress);
                                });
    r.stats.vertices = r.value.vertex_count();
    r.stats.target_faces = opt.target_faces;
    return r;
}

QuadricStats quadric_decimate_in_place(Mesh& mesh, const QuadricOptions& opt, Progress progress) {
    return replace_in_place(mesh, [&](const Mesh& input) { return quadric_decimate(input, opt, progress); });
}

void ReduceOptions::declare_angle(ParamBinder& b) {
    b.add(max_angle_deg, ParamSpec::Float("max_angle_deg", 15.0, 0.1, 89.0, "deg",
                                          "largest angle between the face normals around a removable vertex (the "
                                          "paper: 5 to 40; larger reduces more)"));
    b.add(crease_straightness_deg,
          ParamSpec::Float(
              "crease_straightness", 0.0, 0.0, 30.0, "deg",
              "a vertex in the middle of a crease (two sides, each flat within max_angle_deg, meeting along two "
              "edges that continue each other within this) is removed along the crease, which stays where it "
              "is when straight (a curved one is cut by a chord); 0: off, as in the paper"));
    b.add(hard_surface,
          ParamSpec::Bool("hard_surface", false,
                          "with crease_straightness: on a machined part (every drawing's outline mostly straight, the "
                          "test of hull.plausible's hard_surface, which then keeps the hull) at most 2 degrees, as "
                          "pipelines/paper.yaml sets it: the hull's curved edges keep their vertices; needs the views "
                          "input"));
    b.add(keep_planes_deg,
          ParamSpec::Float("keep_planes", 0.0, 0.0, 30.0, "deg",
                           "refuse collapses that give a face a normal further than this from every normal the "
                           "removed vertex's faces had, so flat sides beside a crease keep their plane instead of "
                           "tilting by up to max_angle_deg; 0: off, as in the paper"));
}

void ReduceOptions::declare_limits(ParamBinder& b) {
    b.add(max_aspect_ratio, ParamSpec::Float("max_aspect_ratio", 0.0, 0.0, 1e6, "",
                                             "refuse collapses that make a face thinner than this (1 = equilateral); "
                                             "0: off, as in the paper"));
    b.add(no_crossings, crossing_guard_param());
    b.add(constrain,
          ParamSpec::Enum("constrain", "none", {"none", "silhouette"},
                          "silhouette: refuse collapses that would move the mesh's outline in a view more than "
                          "`tolerance` away from the drawn silhouette (needs the views input)"),
          {Constrain::None, Constrain::Silhouette});
    b.add(tolerance_px, ParamSpec::Float("tolerance", 1.0, 0.0, 100.0, "px",
                                         "silhouette constraint: how far the outline may move inside or outside the "
                                         "drawn silhouette, in pixels of each view"));
}

void QuadricOptions::declare(ParamBinder& b) {
    b.add(max_error, ParamSpec::Float("max_error", 0.0, 0.0, 1e30, "world units",
                                      "stop before a collapse would move the surface further than this (root mean "
                                      "square distance to the original planes); 0: no limit"));
    b.add(max_normal_deviation_deg, ParamSpec::Float("max_normal_deviation_deg", 45.0, 1.0, 180.0, "deg",
                                                     "refuse collapses that turn a face by more than this"));
    b.add(max_aspect_ratio, ParamSpec::Float("max_aspect_ratio", 20.0, 0.0, 1e6, "",
                                             "refuse collapses that make a face thinner than this (1 = equilateral); "
                                             "0: off"));
    b.add(no_crossings, crossing_guard_param());
}

void DecimateStats::report(Metrics& m) const {
    m.count("faces_before", faces_before);
    m.count("faces", faces_after);
    m.count("vertices", vertices);
    m.metric("face_ratio", faces_before ? double(faces_after) / double(faces_before) : 1.0);
    m.count("collapses", collapses);
    m.count("guard_restarts", restarts);
    if (frozen_vertices) m.count("guard_frozen_vertices", frozen_vertices);
    if (crossings_left)
        m.warn(std::to_string(crossings_left) + " pairs of faces cross each other in the result" +
               (restarts ? " (the input's own, or more than the restarts could remove)" : ""));
    m.warned_count("locked_vertices", locked_vertices,
                   "vertices lie on a boundary or a non-manifold edge and were kept as they are");
}

void QuadricStats::report(Metrics& m) const {
    DecimateStats::report(m);
    m.metric("max_error", max_error);
    if (target_faces && faces_after > target_faces)
        m.warn("stopped at " + std::to_string(faces_after) + " faces, above the target of " +
               std::to_string(target_faces) + ": no further collapse passes the guards");
}

} // namespace cm
