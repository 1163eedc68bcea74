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
    // v's ring (each neighbour follows v in one face), the new faces as indices into it
    // (v replaced by w), and how far the ring reaches from v.
    constexpr int kMax = 64;
    std::uint32_t ring[kMax], before[kMax];
    std::array<int, 3> tris[kMax];
    int nr = 0, nt = 0, iw = -1;
    const Vec3d p(c.point(v));
    double reach3 = 0;
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
    // next from any face visits every face once (otherwise the shortcut below is not taken).
    int next[kMax];
    bool cycle = true;
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
    P2 pr[kMax];
    double sr[kMax];
    for (std::size_t view = 0; view < views_->size(); ++view) {
        const Entry& e = (*views_)[view];
        // A vertex's sample, from the run's samples when given.
        auto at_vertex = [&](std::uint32_t x, const P2& q) {
            return samples ? samples->at(x, view, [&] { return e.sdf.sample(q.x, q.y); }) : e.sdf.sample(q.x, q.y);
        };
        const Vec2d pv2 = e.camera.project(p);
        const P2 pv{pv2.x, pv2.y};
        const double sv = at_vertex(v, pv);
        // Every point of the old and the new faces lies within the ring's reach of v, and the
        // distance is 1-Lipschitz: far inside the drawing the view sees no outline move, and
        // well inside it nothing can reach out.
        const bool ortho = e.camera.orthographic();
        if (ortho && sv + e.camera.scale * reach3 < -tol_) continue;
        double reach2 = 0; // the ring's reach on the image, squared (one root, not one per vertex)
        for (int i = 0; i < nr; ++i) {
            const Vec2d q2 = e.camera.project(Vec3d(c.point(ring[i])));
            pr[i] = {q2.x, q2.y};
            const double dx = pr[i].x - pv.x, dy = pr[i].y - pv.y;
            reach2 = std::max(reach2, dx * dx + dy * dy);
        }
        const double reach = std::sqrt(reach2);
        if (sv + reach < -tol_) continue;
        // Where the view sees v's faces and the new faces all turned one way, both cover the
        // same region (decimate::same_cover): what the view sees is unchanged, and so is the
        // outline.
        if (cycle && nt == nr - 2 && decimate::same_cover(pv, pr, next, nr, tris, nt, reach2)) continue;
        // Recession: v's projection left uncovered by the new faces.
        bool covered = nt == 0;
        double best = std::numeric_limits<double>::infinity();
        P2 q = pv;
        for (int i = 0; i < nt && !covered; ++i) {
            const std::array<P2, 3> t{pr[tris[i][0]], pr[tris[i][1]], pr[tris[i][2]]};
            if (in_triangle(pv, t)) {
                covered = true;
                break;
            }
            for (int k = 0; k < 3; ++k) {
                P2 n;
                const double d = nearest_on_segment(pv, t[std::size_t(k)], t[std::size_t((k + 1) % 3)], n);
                if (d < best) best = d, q = n;
            }
        }
        const bool may_grow = sv + reach > tol_;
        if (covered && !may_grow) continue;
        for (int i = 0; i < nr; ++i) sr[i] = at_vertex(ring[i], pr[i]);
        const P2 pw = pr[iw];
        const double sw = sr[iw];
        auto sq_len = [&](int i) { // the squared length of the edge from w to ring vertex i, on the image
            const double dx = pr[i].x - pw.x, dy = pr[i].y - pw.y;
            return dx * dx + dy * dy;
        };
        auto along = [&](int i, double s) {
            return e.sdf.sample(pw.x + s * (pr[i].x - pw.x), pw.y + s * (pr[i].y - pw.y));
        };
        if (!covered) {
            const double sq = e.sdf.sample(q.x, q.y);
            if (sq < -tol_ && sq < sv) return false;
            // The outline now runs along the new edges between w and the ring's vertices
            // on the outline: none may sag deeper than the tolerance.
            if (sw >= -tol_)
                for (int i = 0; i < nr; ++i) {
                    if (i == iw || sr[i] < -tol_) continue;
                    // The middle first; a quarter of the edge from an end is no deeper than
                    // the deeper-reaching of that end and the middle allows (1-Lipschitz).
                    const double mid = along(i, 0.5);
                    if (mid < -tol_) return false;
                    const double q = 0.25 * std::sqrt(sq_len(i));
                    if (std::max(sw, mid) - q < -tol_ && along(i, 0.25) < -tol_) return false;
                    if (std::max(sr[i], mid) - q < -tol_ && along(i, 0.75) < -tol_) return false;
                }
        }
        // Growth: the new edges from w may not leave the drawing, nor go farther out than their ends.
        if (may_grow)
            for (int i = 0; i < nr; ++i) {
                if (i == iw) continue;
                const double limit = std::max({tol_, sw, sr[i]});
                // No point of the edge is farther out than (sw + sx + length) / 2.
                const double len = std::sqrt(sq_len(i));
                if (sw + sr[i] + len <= 2 * limit) continue;
                // The middle first; a quarter of the edge from an end is no farther out than
                // the nearer of that end and the middle allows (1-Lipschitz).
                const double mid = along(i, 0.5);
                if (mid > limit) return false;
                const double q = 0.25 * len;
                if (std::min(sw, mid) + q > limit && along(i, 0.25) > limit) return false;
                if (std::min(sr[i], mid) + q > limit && along(i, 0.75) > limit) return false;
            }
    }
    return true;
}

} // namespace cm
