#include "outline_guard.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "mesh_decimate_internal.h"

namespace cm {

namespace {

using P2 = decimate::ImagePoint;

double cross2(const P2& a, const P2& b, const P2& c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }

// Whether p lies in the triangle (either orientation; a triangle seen edge-on covers nothing).
bool in_triangle(const P2& p, const std::array<P2, 3>& t) {
    const double d0 = cross2(t[0], t[1], p), d1 = cross2(t[1], t[2], p), d2 = cross2(t[2], t[0], p);
    if (cross2(t[0], t[1], t[2]) == 0) return false;
    return (d0 >= 0 && d1 >= 0 && d2 >= 0) || (d0 <= 0 && d1 <= 0 && d2 <= 0);
}

// The point of segment [a, b] nearest p, and its squared distance.
double nearest_on_segment(const P2& p, const P2& a, const P2& b, P2& q) {
    const P2 ab{b.x - a.x, b.y - a.y};
    const double len2 = ab.x * ab.x + ab.y * ab.y;
    double t = len2 > 0 ? ((p.x - a.x) * ab.x + (p.y - a.y) * ab.y) / len2 : 0.0;
    t = std::clamp(t, 0.0, 1.0);
    q = {a.x + t * ab.x, a.y + t * ab.y};
    return (p.x - q.x) * (p.x - q.x) + (p.y - q.y) * (p.y - q.y);
}

constexpr int kMax = 64; // faces around a vertex the guard looks at; a vertex with more stays

// A collapse of v into w as the views see it: v's ring (each neighbour follows v in one face),
// the new faces as indices into it (v replaced by w), and how far the ring reaches from v.
// Trivially constructible arrays: the guard makes one per collapse asked about.
struct CollapseFan {
    std::uint32_t v;
    Vec3d p; ///< v's position
    std::uint32_t ring[kMax];
    std::array<int, 3> tris[kMax];
    int next[kMax]; ///< face i is (v, ring[i], ring[next[i]]), when `cycle`
    int nr = 0, nt = 0, iw = -1;
    bool cycle = true; ///< following next from any face visits every face once
    double reach3 = 0;

    /// False when v has kMax faces or more, or w is not on its ring.
    bool gather(const decimate::Collapser& c, std::uint32_t v, std::uint32_t w);
};

bool CollapseFan::gather(const decimate::Collapser& c, std::uint32_t vertex, std::uint32_t w) {
    v = vertex;
    p = Vec3d(c.point(v));
    std::uint32_t before[kMax];
    c.for_faces(v, [&](std::uint32_t f) {
        if (nr == kMax) return;
        const auto& t = c.tri(f);
        const int k = t[0] == v ? 0 : (t[1] == v ? 1 : 2);
        const std::uint32_t x = t[std::size_t((k + 1) % 3)];
        if (x == w) iw = nr;
        reach3 = std::max(reach3, length(Vec3d(c.point(x)) - p));
        before[nr] = t[std::size_t((k + 2) % 3)];
        ring[nr++] = x;
    });
    if (nr == kMax || iw < 0) return false;
    auto index = [&](std::uint32_t x) { return int(std::find(ring, ring + nr, x) - ring); };
    // The faces around v as one cycle: face i is (v, ring[i], ring[next[i]]), and following
    // next from any face visits every face once (otherwise the shortcut of same_cover is not taken).
    for (int i = 0; i < nr && cycle; ++i) cycle = (next[i] = index(before[i])) < nr;
    if (cycle) {
        int i = 0, steps = 0;
        do i = next[i], ++steps;
        while (i != 0 && steps <= nr);
        cycle = steps == nr;
    }
    c.for_faces(v, [&](std::uint32_t f) {
        const auto& t = c.tri(f);
        if (t[0] == w || t[1] == w || t[2] == w) return;
        auto& n = tris[nt++];
        for (int k = 0; k < 3; ++k) n[std::size_t(k)] = t[std::size_t(k)] == v ? iw : index(t[std::size_t(k)]);
    });
    return true;
}

// One view's look at a collapse (see the top of outline_guard.h): the fan projected onto its
// image, and the drawing's signed distance (negative inside, in its pixels) at the fan's vertices.
class ViewLook {
public:
    ViewLook(const ViewSdf& e, std::size_t view, const CollapseFan& fan, OutlineGuard::Samples* samples, double tol)
        : e_(e), view_(view), fan_(fan), samples_(samples), tol_(tol) {}
    /// Whether the collapse keeps this view's outline within the tolerance of the drawing.
    bool keeps(const decimate::Collapser& c);

private:
    /// A vertex's distance, from the run's samples when given.
    double at_vertex(std::uint32_t x, const P2& q) {
        return samples_ ? samples_->at(x, view_, [&] { return e_.sdf.sample(q.x, q.y); }) : e_.sdf.sample(q.x, q.y);
    }
    /// The squared length of the new edge from w to ring vertex i, on the image.
    double sq_len(int i) const {
        const double dx = pr_[i].x - pw_.x, dy = pr_[i].y - pw_.y;
        return dx * dx + dy * dy;
    }
    /// The distance at the point `s` along the new edge from w to ring vertex i.
    double along(int i, double s) const {
        return e_.sdf.sample(pw_.x + s * (pr_[i].x - pw_.x), pw_.y + s * (pr_[i].y - pw_.y));
    }
    /// Whether the new faces cover v's projection; if not, `q` is their nearest point to it.
    bool covered(P2& q) const;
    /// Recession: the outline moves to `q` (v's projection left uncovered); whether it goes
    /// deeper than the tolerance inside the drawing, there or along the new edges.
    bool recedes(const P2& q) const;
    /// Growth: whether the new edges from w leave the drawing, or go farther out than their ends.
    bool grows() const;

    const ViewSdf& e_;
    const std::size_t view_;
    const CollapseFan& fan_;
    OutlineGuard::Samples* samples_;
    const double tol_;
    P2 pv_, pw_;      ///< v and w on the image
    double sv_, sw_;  ///< their distances
    P2 pr_[kMax];     ///< the ring on the image
    double sr_[kMax]; ///< its distances
};

bool ViewLook::keeps(const decimate::Collapser& c) {
    const CollapseFan& f = fan_;
    const Vec2d pv2 = e_.camera.project(f.p);
    pv_ = {pv2.x, pv2.y};
    sv_ = at_vertex(f.v, pv_);
    // Every point of the old and the new faces lies within the ring's reach of v, and the
    // distance is 1-Lipschitz: far inside the drawing the view sees no outline move, and
    // well inside it nothing can reach out.
    const bool ortho = e_.camera.orthographic();
    if (ortho && sv_ + e_.camera.scale * f.reach3 < -tol_) return true;
    double reach2 = 0; // the ring's reach on the image, squared (one root, not one per vertex)
    for (int i = 0; i < f.nr; ++i) {
        const Vec2d q2 = e_.camera.project(Vec3d(c.point(f.ring[i])));
        pr_[i] = {q2.x, q2.y};
        const double dx = pr_[i].x - pv_.x, dy = pr_[i].y - pv_.y;
        reach2 = std::max(reach2, dx * dx + dy * dy);
    }
    const double reach = std::sqrt(reach2);
    if (sv_ + reach < -tol_) return true;
    // Where the view sees v's faces and the new faces all turned one way, both cover the
    // same region (decimate::same_cover): what the view sees is unchanged, and so is the
    // outline.
    if (f.cycle && f.nt == f.nr - 2 && decimate::same_cover(pv_, pr_, f.next, f.nr, f.tris, f.nt, reach2)) return true;
    P2 q = pv_;
    const bool cover = covered(q);
    const bool may_grow = sv_ + reach > tol_;
    if (cover && !may_grow) return true;
    for (int i = 0; i < f.nr; ++i) sr_[i] = at_vertex(f.ring[i], pr_[i]);
    pw_ = pr_[f.iw];
    sw_ = sr_[f.iw];
    if (!cover && recedes(q)) return false;
    return !may_grow || !grows();
}

bool ViewLook::covered(P2& q) const {
    const CollapseFan& f = fan_;
    if (f.nt == 0) return true;
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i < f.nt; ++i) {
        const std::array<P2, 3> t{pr_[f.tris[i][0]], pr_[f.tris[i][1]], pr_[f.tris[i][2]]};
        if (in_triangle(pv_, t)) return true;
        for (int k = 0; k < 3; ++k) {
            P2 n;
            const double d = nearest_on_segment(pv_, t[std::size_t(k)], t[std::size_t((k + 1) % 3)], n);
            if (d < best) best = d, q = n;
        }
    }
    return false;
}

bool ViewLook::recedes(const P2& q) const {
    const CollapseFan& f = fan_;
    const double sq = e_.sdf.sample(q.x, q.y);
    if (sq < -tol_ && sq < sv_) return true;
    // The outline now runs along the new edges between w and the ring's vertices on the
    // outline: none may sag deeper than the tolerance.
    if (sw_ < -tol_) return false;
    for (int i = 0; i < f.nr; ++i) {
        if (i == f.iw || sr_[i] < -tol_) continue;
        // The middle first; a quarter of the edge from an end is no deeper than the
        // deeper-reaching of that end and the middle allows (1-Lipschitz).
        const double mid = along(i, 0.5);
        if (mid < -tol_) return true;
        const double quarter = 0.25 * std::sqrt(sq_len(i));
        if (std::max(sw_, mid) - quarter < -tol_ && along(i, 0.25) < -tol_) return true;
        if (std::max(sr_[i], mid) - quarter < -tol_ && along(i, 0.75) < -tol_) return true;
    }
    return false;
}

bool ViewLook::grows() const {
    const CollapseFan& f = fan_;
    for (int i = 0; i < f.nr; ++i) {
        if (i == f.iw) continue;
        const double limit = std::max({tol_, sw_, sr_[i]});
        // No point of the edge is farther out than (sw + sx + length) / 2.
        const double len = std::sqrt(sq_len(i));
        if (sw_ + sr_[i] + len <= 2 * limit) continue;
        // The middle first; a quarter of the edge from an end is no farther out than the
        // nearer of that end and the middle allows (1-Lipschitz).
        const double mid = along(i, 0.5);
        if (mid > limit) return true;
        const double quarter = 0.25 * len;
        if (std::min(sw_, mid) + quarter > limit && along(i, 0.25) > limit) return true;
        if (std::min(sr_[i], mid) + quarter > limit && along(i, 0.75) > limit) return true;
    }
    return false;
}

} // namespace

// The faces around pv make a fan over the closed ring (r_i to r_next[i], all of them): a
// point x lies in as many of its faces, counted with their turn (+1 one way, -1 the other), as
// the ring winds around x, since the fan's spokes cancel. The new faces make a fan from w over
// the same closed ring (the two faces at w are gone, and w's spokes cancel alike), with the same
// count. When every face, old and new, turns the same way, each count is the number of faces
// holding x, and both fans cover {x : the ring winds around x} (up to their edges).
bool decimate::same_cover(const P2& pv, const P2* ring, const int* next, int nr, const std::array<int, 3>* tris, int nt,
                          double reach2) {
    // Rounding of a cross product of image coordinates (a few thousand pixels) is far below
    // this; a face seen nearly edge-on is left to the full test.
    const double margin = 1e-9 * std::max(reach2, 1.0);
    bool positive = false;
    for (int i = 0; i < nr; ++i) {
        const double d = cross2(pv, ring[i], ring[next[i]]);
        if (!(std::fabs(d) > margin)) return false;
        if (i == 0) positive = d > 0;
        else if ((d > 0) != positive) return false;
    }
    for (int i = 0; i < nt; ++i) {
        const double d = cross2(ring[tris[i][0]], ring[tris[i][1]], ring[tris[i][2]]);
        if (!(std::fabs(d) > margin) || (d > 0) != positive) return false;
    }
    return true;
}

OutlineGuard::OutlineGuard(const Views& views, double tolerance_px) : views_(view_sdfs(views)), tol_(tolerance_px) {}

bool OutlineGuard::keeps(const decimate::Collapser& c, std::uint32_t v, std::uint32_t w, Samples* samples) const {
    CollapseFan fan;
    if (!fan.gather(c, v, w)) return false;
    for (std::size_t view = 0; view < views_.size(); ++view)
        if (!ViewLook(views_[view], view, fan, samples, tol_).keeps(c)) return false;
    return true;
}

} // namespace cm
