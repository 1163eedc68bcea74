// The bend of what still disagrees once views are reconciled, and the warnings on what moved
// (reconcile.h).
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "reconcile_state.h"

namespace cm::reconcile_detail {

// What the views still disagree on, once reconciled: a drawing's line of sight the others
// cut away entirely. Where the others' silhouettes come within the tolerance of letting it
// through, they are bent there (the cells each must cover, reconcile_warp.cpp bends it
// over them); beyond it the bend is refused and the user told.
void Reconciler::bend() {
    const ReconcileGrid g = grid(fine_cells_);
    const std::vector<AxisMask> m = member_masks(g), gm = group_masks(m, "union");
    std::vector<const AxisMask*> all;
    for (const auto& x : gm) all.push_back(&x);
    std::vector<std::vector<float>> dist;
    std::vector<double> px, tol; // pixels per cell and the tolerance in pixels, per line of sight
    for (std::size_t q = 0; q < groups_.size(); ++q) {
        dist.push_back(distance_to_mask(g, gm[q]));
        double scale = 1e300, longest = 0;
        for (std::size_t k : groups_[q]) {
            const View& v = views_.views[members_[k].index];
            const Coverage::Box& b = v.coverage.inside_box();
            scale = std::min(scale, v.camera.scale);
            longest = std::max({longest, double(b.x1 - b.x0 + 1), double(b.y1 - b.y0 + 1)});
        }
        px.push_back(std::min(g.h[std::size_t(gm[q].a)], g.h[std::size_t(gm[q].b)]) * scale);
        tol.push_back(opt_.bend * longest);
    }
    std::vector<AxisMask> add = gm;
    for (auto& a : add) std::fill(a.in.begin(), a.in.end(), 0);
    auto cell_of = [&](const AxisMask& q, const std::array<int, 3>& idx) {
        return std::size_t(idx[std::size_t(q.a)]) +
               std::size_t(g.n[std::size_t(q.a)]) * std::size_t(idx[std::size_t(q.b)]);
    };
    for (std::size_t k = 0; k < members_.size(); ++k) {
        const std::size_t own = group_of_[k];
        const AxisMask& mk = m[k];
        const auto miss = missing_cells(g, mk, all);
        const int c = 3 - mk.a - mk.b, na = g.n[std::size_t(mk.a)];
        std::vector<std::size_t> refused(groups_.size(), 0);
        std::vector<double> refused_px(groups_.size(), 0.0);
        double inside = 0;
        for (std::size_t cell = 0; cell < miss.size(); ++cell) {
            inside += mk.in[cell];
            if (!miss[cell] || !gm[own].in[cell]) continue; // intersect leaves that out on purpose
            std::array<int, 3> idx{0, 0, 0};
            idx[std::size_t(mk.a)] = int(cell % std::size_t(na)), idx[std::size_t(mk.b)] = int(cell / std::size_t(na));
            // The depth the line of sight passes at: of those within the tolerance in every
            // view, the one that grows the views least (the pixels each must grow, what an
            // earlier line already grew counting nothing), so that each bend moves no more
            // outline than it must; if none is within, the nearest (refused, below).
            double best = 1e300, best_area = 1e300;
            int best_k = 0;
            for (int z = 0; z < g.n[std::size_t(c)]; ++z) {
                idx[std::size_t(c)] = z;
                double cost = 0, area = 0;
                for (std::size_t q = 0; q < groups_.size(); ++q) {
                    if (q == own) continue;
                    const std::size_t at = cell_of(gm[q], idx);
                    cost = std::max(cost, dist[q][at] * px[q] / tol[q]);
                    area += add[q].in[at] ? 0.0 : dist[q][at] * px[q];
                }
                if (cost <= 1.0 ? best > 1.0 || area < best_area : best > 1.0 && cost < best)
                    best = cost, best_area = area, best_k = z;
            }
            idx[std::size_t(c)] = best_k;
            for (std::size_t q = 0; q < groups_.size(); ++q) {
                if (q == own) continue;
                const double d = dist[q][cell_of(gm[q], idx)] * px[q];
                if (best <= 1.0) {
                    if (d > 0) add[q].in[cell_of(gm[q], idx)] = 1;
                } else if (d > tol[q]) {
                    ++refused[q];
                    refused_px[q] = std::max(refused_px[q], d);
                }
            }
        }
        for (std::size_t q = 0; q < groups_.size(); ++q) {
            if (!(refused[q] > 0.001 * inside)) continue;
            std::ostringstream os;
            os << std::fixed << std::setprecision(1) << "view \""
               << views_.views[members_[groups_[q].front()].index].name << "\" would have to bend " << refused_px[q]
               << " px (tolerance " << tol[q] << " px) to agree with \"" << views_.views[members_[k].index].name
               << "\"; not bent there: " << 100.0 * refused[q] / inside << " % of \""
               << views_.views[members_[k].index].name << "\" stays cut";
            warnings_.push_back(os.str());
        }
    }
    // The bends: each added cell covered, by a smooth warp, in every view of its line of sight.
    for (std::size_t q = 0; q < groups_.size(); ++q)
        for (std::size_t k : groups_[q]) {
            const int a = add[q].a, b = add[q].b, na = g.n[std::size_t(a)];
            std::vector<std::array<double, 4>> rects; // x0, y0, x1, y1 in the view's pixels
            for (std::size_t cell = 0; cell < add[q].in.size(); ++cell) {
                if (!add[q].in[cell]) continue;
                std::array<double, 4> r{1e300, 1e300, -1e300, -1e300};
                for (int corner = 0; corner < 4; ++corner) {
                    Vec3d p{0, 0.5 * size_[1], 0};
                    p[a] = g.lo[a] + (double(cell % std::size_t(na)) + (corner & 1)) * g.h[std::size_t(a)];
                    p[b] = g.lo[b] + (double(cell / std::size_t(na)) + (corner >> 1)) * g.h[std::size_t(b)];
                    const Vec2d s = views_.views[members_[k].index].camera.project(p);
                    r = {std::min(r[0], s.x), std::min(r[1], s.y), std::max(r[2], s.x), std::max(r[3], s.y)};
                }
                rects.push_back(r);
            }
            warp_px_[k] = std::max(warp_px_[k], warp(members_[k], rects, tol[q]));
        }
}

// One line per view moved beyond the tolerance: stretched one axis against the other
// (against the primary's scale; a view drawn larger all over is not news) or turned.
void Reconciler::warn_moved(const Member& m, const ViewReconciliation& r) {
    const bool uneven = std::abs(r.scale_x / r.scale_y - 1) > opt_.tolerance;
    const bool turned = std::abs(std::sin(m.T.theta)) > opt_.tolerance;
    if (!uneven && !turned) return;
    std::vector<std::string> parts;
    std::ostringstream os;
    os << std::fixed << std::setprecision(1);
    if (uneven)
        for (const auto& [k, axis] : {std::pair{r.scale_x, m.ar}, std::pair{r.scale_y, m.au}})
            if (std::abs(k - 1) > 0.5 * opt_.tolerance) {
                std::ostringstream p;
                p << std::fixed << std::setprecision(1) << (k > 1 ? "stretched " : "shrunk ") << 100.0 * std::abs(k - 1)
                  << " % in " << axis_word(axis);
                parts.push_back(p.str());
            }
    if (turned) {
        std::ostringstream p;
        p << std::fixed << std::setprecision(1) << "turned " << std::abs(m.T.theta) / kDeg << " deg";
        parts.push_back(p.str());
    }
    if (parts.empty()) return;
    std::vector<std::string> with;
    for (const Member& o : members_)
        if (&o != &m && (o.ar == m.ar || o.ar == m.au || o.au == m.ar || o.au == m.au)) {
            const std::string n = "\"" + views_.views[o.index].name + "\"";
            if (o.primary) with.insert(with.begin(), n);
            else with.push_back(n);
        }
    os << "view \"" << views_.views[m.index].name << "\" ";
    for (std::size_t i = 0; i < parts.size(); ++i) os << (i ? " and " : "") << parts[i];
    os << " to agree with ";
    for (std::size_t i = 0; i < with.size(); ++i) os << (i ? " and " : "") << with[i];
    os << "; " << r.missing_pct << " % of it not modelled";
    warnings_.push_back(os.str());
}

} // namespace cm::reconcile_detail
