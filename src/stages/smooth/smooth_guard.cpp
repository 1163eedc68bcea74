#include "smooth_guard.h"

#include <algorithm>
#include <array>
#include <atomic>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "geometry/mesh_intersect.h"

namespace cm {

namespace {

// Two vertices closer than this fraction of the bounding-box diagonal count as drawn onto
// one another: ten times the output check's kCoincidentTolerance, so what the guard leaves
// apart stays apart in `conceptmesh check` and in an importer's merge by distance.
constexpr double kSeparation = 10 * kCoincidentTolerance;

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

void sort_unique(std::vector<std::uint32_t>& v) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
}

// The umbrella operator (factor 1) draws two vertices with the same ring of neighbours (the
// two tips of a thin part, one cell across) onto the ring's centroid: an importer welds them
// and the mesh is pinched there. The guard finds such vertices and the bad faces, then pulls
// their vertices back round by round.
//
// The first check covers every face at the smoothed positions, with an index of the faces
// there (one pose: smaller boxes, fewer entries than an index of everything between input and
// smoothed). The faces around vertices pulled back are then at blends of the two, which
// that index does not hold: they go into a second, small index covering both poses, and a
// face checked in a later round is asked of both.
class Guard {
public:
    Guard(const Mesh& in, std::vector<Vec3f>& p, SmoothStats& st)
        : in_(in),
          p_(p),
          st_(st),
          smoothed_(p),
          fans_(embedded_fans(in.triangles, smoothed_)),
          index_(in.triangles, smoothed_),
          box_(box_of(in)),
          separation_(kSeparation * length(Vec3d(box_[1]) - Vec3d(box_[0]))),
          input_answer_(p.size(), 0),
          coincidence_(p, separation_),
          together_(coincidence_.all()) {}

    /// Step 1: every face and vertex at the smoothed positions. False when nothing is bad.
    bool check_all() {
        collect(index_.all(p_, {}, &fans_), nullptr);
        st_.bad_faces = bad_.size();
        st_.coincident = badv_.size();
        return !bad_.empty() || !badv_.empty();
    }

    /// Step 2: pulls back round by round until nothing is bad, or only the input's own faces are.
    void mend() {
        weight_.assign(p_.size(), 1.0f);
        face_moved_.assign(in_.triangles.size(), 0);
        marked_.assign(p_.size(), 0);
        while (!bad_.empty() || !badv_.empty())
            if (!pull_back_round()) break;
    }

private:
    static std::array<Vec3f, 2> box_of(const Mesh& in) {
        std::array<Vec3f, 2> b;
        in.bounds(b[0], b[1]);
        return b;
    }

    // Whether the vertices `vs` (together at p) were together in the input already: asked only
    // about new ones, in one pass over the input per batch (an index of the asked vertices'
    // input positions, which each input vertex looks itself up in; no index of the whole
    // input beside the one of p). input_answer_: 0 not asked yet, 1 together in the input, 2 apart.
    void ask_input(const std::vector<std::uint32_t>& vs);
    // The bad faces (`pairs` crossing, and those of `only`, or all, turned or collapsed) and
    // the vertices drawn onto another that were apart in the input.
    void collect(const std::vector<FacePair>& pairs, const std::vector<std::uint32_t>* only);
    // The box of every blend of face f's two poses, and of its pose now.
    SelfIntersectionIndex::Box swept(std::uint32_t f) const;
    SelfIntersectionIndex::Box box_now(std::uint32_t f) const;
    // The crossing pairs at p with a face in `faces`: the other face is in index_ at its
    // smoothed position, or among the moving faces.
    std::vector<FacePair> crossings_of(const std::vector<std::uint32_t>& faces, const SelfIntersectionIndex& moving);
    // One round: the vertices of the bad faces (and the bad vertices) halfway back, the
    // coincidences and faces around them checked again. False when none could move.
    bool pull_back_round();
    void pull_back(std::uint32_t v);

    const Mesh& in_;
    std::vector<Vec3f>& p_;
    SmoothStats& st_;
    const std::vector<Vec3f> smoothed_;
    // The fans that lie over a plane one-to-one: pairs of their faces need no crossing test
    // (nine in ten of the pairs the index finds on a smooth surface).
    const std::vector<char> fans_;
    const SelfIntersectionIndex index_;
    const std::array<Vec3f, 2> box_; // the input's bounding box
    const double separation_;
    std::vector<char> input_answer_;
    // Vertices within the separation of another at p, kept up to date as vertices move: a
    // vertex's answer changes only when it or a vertex near it (before or after) moves.
    CoincidenceIndex coincidence_;
    std::vector<std::uint32_t> together_, recheck_;
    std::vector<std::uint32_t> bad_, badv_; // faces, and vertices drawn onto another
    std::vector<float> weight_;             // position = input + weight * (smoothed - input)
    // Faces to re-check, vertices moved this round, and the faces the index holds at a moved
    // vertex's smoothed position (those around the vertex among them: no table of the faces
    // around every vertex is built for the few that move).
    std::vector<std::uint32_t> check_, moved_, near_faces_;
    // The faces that ever had a vertex pulled back (their triangles, and their faces in `in`).
    std::vector<char> face_moved_;
    std::vector<std::array<std::uint32_t, 3>> moving_tris_;
    std::vector<std::uint32_t> moving_faces_;
    std::vector<char> marked_;
};

void Guard::ask_input(const std::vector<std::uint32_t>& vs) {
    std::vector<std::uint32_t> asked;
    std::vector<Vec3f> where;
    for (auto v : vs)
        if (!input_answer_[v]) {
            asked.push_back(v);
            where.push_back(in_.positions[v]);
        }
    if (asked.empty()) return;
    const CoincidenceIndex index_of_asked(where, separation_);
    // A coarse grid over the input's box marks the cells within twice the separation of an
    // asked vertex: only the input vertices in marked cells can be near one, and only they
    // look themselves up (the same answers, for a bit test per vertex elsewhere).
    constexpr int kGrid = 128;
    const Vec3d origin(box_[0]), span = vmax(Vec3d(box_[1]) - origin, Vec3d(1e-30, 1e-30, 1e-30));
    const Vec3d per(kGrid / span.x, kGrid / span.y, kGrid / span.z);
    auto cell_of = [&](double x, int a) {
        const double t = (x - origin[a]) * per[a];
        return t >= 0 ? int(std::min(t, double(kGrid - 1))) : 0; // NaN to 0 (near nothing anyway)
    };
    std::vector<char> marked_cells(std::size_t(kGrid) * kGrid * kGrid, 0);
    for (const Vec3f& q : where) {
        int c0[3], c1[3];
        for (int a = 0; a < 3; ++a) {
            c0[a] = cell_of(double(q[a]) - 2 * separation_, a);
            c1[a] = cell_of(double(q[a]) + 2 * separation_, a);
        }
        for (int z = c0[2]; z <= c1[2]; ++z)
            for (int y = c0[1]; y <= c1[1]; ++y)
                for (int x = c0[0]; x <= c1[0]; ++x)
                    marked_cells[(std::size_t(z) * kGrid + std::size_t(y)) * kGrid + std::size_t(x)] = 1;
    }
    std::vector<char> hit(asked.size(), 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, in_.positions.size(), 1 << 14), [&](const auto& r) {
        for (std::size_t w = r.begin(); w != r.end(); ++w) {
            const Vec3f& q = in_.positions[w];
            const std::size_t cell = (std::size_t(cell_of(q.z, 2)) * kGrid + std::size_t(cell_of(q.y, 1))) * kGrid +
                                     std::size_t(cell_of(q.x, 0));
            if (!marked_cells[cell]) continue;
            index_of_asked.near_point(q, [&](std::uint32_t k) {
                if (asked[k] != w) std::atomic_ref<char>(hit[k]).store(1, std::memory_order_relaxed);
            });
        }
    });
    for (std::size_t k = 0; k < asked.size(); ++k) input_answer_[asked[k]] = hit[k] ? 1 : 2;
}

void Guard::collect(const std::vector<FacePair>& pairs, const std::vector<std::uint32_t>* only) {
    bad_.clear();
    for (const auto& pr : pairs) {
        bad_.push_back(pr[0]);
        bad_.push_back(pr[1]);
    }
    find_bad_shapes(in_, p_, only, bad_);
    sort_unique(bad_);
    badv_.clear();
    ask_input(together_);
    for (auto v : together_)
        if (input_answer_[v] == 2) badv_.push_back(v);
    ++st_.guard_rounds;
}

SelfIntersectionIndex::Box Guard::swept(std::uint32_t f) const {
    const auto& t = in_.triangles[f];
    SelfIntersectionIndex::Box b{in_.positions[t[0]], in_.positions[t[0]]};
    for (const auto* pose : {&in_.positions, &smoothed_})
        for (auto v : t) b = {vmin(b.lo, (*pose)[v]), vmax(b.hi, (*pose)[v])};
    return b;
}

SelfIntersectionIndex::Box Guard::box_now(std::uint32_t f) const {
    const auto& t = in_.triangles[f];
    return SelfIntersectionIndex::Box{vmin(p_[t[0]], vmin(p_[t[1]], p_[t[2]])),
                                      vmax(p_[t[0]], vmax(p_[t[1]], p_[t[2]]))};
}

std::vector<FacePair> Guard::crossings_of(const std::vector<std::uint32_t>& faces,
                                          const SelfIntersectionIndex& moving) {
    auto meet = [](const SelfIntersectionIndex::Box& a, const SelfIntersectionIndex::Box& b) {
        return !(a.lo.x > b.hi.x || b.lo.x > a.hi.x || a.lo.y > b.hi.y || b.lo.y > a.hi.y || a.lo.z > b.hi.z ||
                 b.lo.z > a.hi.z);
    };
    tbb::enumerable_thread_specific<std::vector<FacePair>> found;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, faces.size(), 64), [&](const auto& r) {
        auto& local = found.local();
        std::vector<std::uint32_t> near, more;
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            const std::uint32_t fa = faces[i];
            const SelfIntersectionIndex::Box reach = swept(fa), now = box_now(fa);
            index_.candidates(reach, near);
            moving.candidates(reach, more);
            for (auto& k : more) k = moving_faces_[k];
            near.insert(near.end(), more.begin(), more.end());
            sort_unique(near);
            for (std::uint32_t fb : near)
                if (fb != fa && meet(now, box_now(fb)) && triangles_cross(p_, in_.triangles[fa], in_.triangles[fb]))
                    local.push_back({std::min(fa, fb), std::max(fa, fb)});
        }
    });
    return merged_pairs(found);
}

void Guard::pull_back(std::uint32_t v) {
    if (marked_[v] || weight_[v] == 0.0f) return;
    marked_[v] = 1;
    moved_.push_back(v);
    weight_[v] = weight_[v] > 0.3f ? weight_[v] * 0.5f : 0.0f;
    p_[v] = in_.positions[v] + (smoothed_[v] - in_.positions[v]) * weight_[v];
}

bool Guard::pull_back_round() {
    moved_.clear();
    for (auto f : bad_)
        for (auto v : in_.triangles[f]) pull_back(v);
    for (auto v : badv_) pull_back(v);
    if (moved_.empty()) { // the input's own faces
        st_.unresolved = bad_.size();
        return false;
    }
    st_.pulled_back += moved_.size();
    recheck_ = together_; // those together before, those moved and those they now meet
    for (auto v : moved_) coincidence_.moved(v);
    for (auto v : moved_) {
        recheck_.push_back(v);
        coincidence_.near(v, [&](std::uint32_t w) { recheck_.push_back(w); });
    }
    sort_unique(recheck_);
    together_.clear();
    for (auto v : recheck_)
        if (coincidence_.has_near(v)) together_.push_back(v);
    check_.clear();
    for (auto v : moved_) {
        marked_[v] = 0;
        index_.faces_near(smoothed_[v], near_faces_);
        for (auto f : near_faces_) {
            const auto& t = in_.triangles[f];
            if (t[0] == v || t[1] == v || t[2] == v) check_.push_back(f);
        }
    }
    sort_unique(check_);
    for (auto f : check_)
        if (!face_moved_[f]) {
            face_moved_[f] = 1;
            moving_tris_.push_back(in_.triangles[f]);
            moving_faces_.push_back(f);
        }
    const SelfIntersectionIndex moving(moving_tris_, in_.positions, &smoothed_);
    collect(crossings_of(check_, moving), &check_);
    return true;
}

} // namespace

void guard_surface(const Mesh& in, std::vector<Vec3f>& p, SmoothStats& st) {
    Guard guard(in, p, st);
    if (guard.check_all()) guard.mend();
}

} // namespace cm
