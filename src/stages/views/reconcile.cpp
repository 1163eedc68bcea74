#include "reconcile.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include <tbb/parallel_for.h>

#include "align.h"
#include "reconcile_state.h"
#include "silhouette_extent.h"

namespace cm {

namespace reconcile_detail {
void Reconciler::setup() {
    for (std::size_t i = 0; i < views_.views.size(); ++i) {
        const View& v = views_.views[i];
        const int ar = axis_of(v.camera.r), au = axis_of(v.camera.u);
        if (!v.camera.orthographic() || ar < 0 || au < 0) continue;
        Member m;
        m.index = i, m.ar = ar, m.au = au, m.primary = i == opt_.primary;
        const Extent e = silhouette_extent(v);
        const Coverage::Box& b = v.coverage.inside_box();
        double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
        for (int y = b.y0; y <= b.y1; ++y)
            for (int x = b.x0; x <= b.x1; ++x)
                if (v.inside(x, y) &&
                    (!v.inside(x - 1, y) || !v.inside(x + 1, y) || !v.inside(x, y - 1) || !v.inside(x, y + 1))) {
                    m.boundary.push_back({x + 0.5, y + 0.5});
                    x0 = std::min(x0, x + 0.5), x1 = std::max(x1, x + 0.5);
                    y0 = std::min(y0, y + 0.5), y1 = std::max(y1, y + 0.5);
                }
        m.pad = {0.5 * ((e.x1 - e.x0) - (x1 - x0)), 0.5 * ((e.y1 - e.y0) - (y1 - y0))};
        m.T.c = {0.5 * (e.x0 + e.x1), 0.5 * (e.y0 + e.y1)};
        m.cam = v.camera;
        members_.push_back(std::move(m));
    }
    // Lines of sight: axis views over the same two world axes.
    group_of_.assign(members_.size(), 0);
    for (std::size_t k = 0; k < members_.size(); ++k) {
        const int key = std::min(members_[k].ar, members_[k].au) * 3 + std::max(members_[k].ar, members_[k].au);
        std::size_t g = 0;
        while (g < groups_.size()) {
            const Member& f = members_[groups_[g].front()];
            if (std::min(f.ar, f.au) * 3 + std::max(f.ar, f.au) == key) break;
            ++g;
        }
        if (g == groups_.size()) groups_.emplace_back();
        if (members_[k].primary) groups_[g].insert(groups_[g].begin(), k);
        else groups_[g].push_back(k);
        group_of_[k] = g;
    }
    warp_px_.assign(members_.size(), 0.0);
    anchor_.resize(members_.size());
    for (const auto& g : groups_)
        for (std::size_t k : g) anchor_[k] = g.front();
}

// From each member's turn: its extents turned, then (a few rounds) the box (the primary's
// axes as drawn, the others the geometric mean of the views measuring them) and each view's
// scale (as the alignment sets it, from its turned extents), each stretch and shift, and the
// cameras placed as the alignment places them, on the new box. A view that shares its line
// of sight with an earlier one (its anchor: front for back) follows the anchor's scale, so
// that what one draws and the other does not is not stretched away.
void Reconciler::fit() {
    for (Member& m : members_) {
        const double cs = std::cos(m.T.theta), sn = std::sin(m.T.theta);
        double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
        for (const Vec2d& p : m.boundary) {
            const double dx = p.x - m.T.c.x, dy = p.y - m.T.c.y;
            const double rx = cs * dx - sn * dy, ry = sn * dx + cs * dy;
            x0 = std::min(x0, rx), x1 = std::max(x1, rx), y0 = std::min(y0, ry), y1 = std::max(y1, ry);
        }
        m.w = x1 - x0 + 2 * m.pad.x, m.h = y1 - y0 + 2 * m.pad.y;
        m.mid = {0.5 * (x0 + x1), 0.5 * (y0 + y1)};
    }
    std::vector<double> s;
    for (const Member& m : members_) s.push_back(views_.views[m.index].camera.scale);
    const Vec3d ext = views_.bounds_max - views_.bounds_min;
    for (int round = 0; round < 4; ++round) {
        std::array<double, 3> lsum{0, 0, 0}, lcnt{0, 0, 0}, fixed{-1, -1, -1};
        for (std::size_t k = 0; k < members_.size(); ++k) {
            const Member& m = members_[k];
            if (anchor_[k] != k) continue;
            if (m.primary) fixed[std::size_t(m.ar)] = m.w / s[k], fixed[std::size_t(m.au)] = m.h / s[k];
            lsum[std::size_t(m.ar)] += std::log(m.w / s[k]), ++lcnt[std::size_t(m.ar)];
            lsum[std::size_t(m.au)] += std::log(m.h / s[k]), ++lcnt[std::size_t(m.au)];
        }
        for (std::size_t a = 0; a < 3; ++a)
            size_[a] = fixed[a] > 0 ? fixed[a] : lcnt[a] > 0 ? std::exp(lsum[a] / lcnt[a]) : ext[int(a)];
        for (std::size_t k = 0; k < members_.size(); ++k)
            if (!members_[k].primary && anchor_[k] == k)
                s[k] = std::sqrt(members_[k].w / size_[std::size_t(members_[k].ar)] * members_[k].h /
                                 size_[std::size_t(members_[k].au)]);
    }
    const Vec3d mid{0, 0.5 * size_[1], 0};
    for (std::size_t k = 0; k < members_.size(); ++k) {
        Member& m = members_[k];
        if (m.primary) m.T.kx = m.T.ky = 1.0;
        else if (anchor_[k] == k) {
            m.T.kx = s[k] * size_[std::size_t(m.ar)] / m.w;
            m.T.ky = s[k] * size_[std::size_t(m.au)] / m.h;
            // uniform: the drawing keeps its proportions (one scale, as the alignment's).
            if (opt_.stretch == "uniform") m.T.kx = m.T.ky = std::sqrt(m.T.kx * m.T.ky);
        } else {
            // The anchor's drawn pixels per unit along each axis, as this view's.
            const Member& a = members_[anchor_[k]];
            const double ar = s[anchor_[k]] / (a.ar == m.ar ? a.T.kx : a.T.ky);
            const double au = s[anchor_[k]] / (a.au == m.au ? a.T.ky : a.T.kx);
            m.T.kx = s[k] / ar, m.T.ky = s[k] / au;
        }
        m.T.t = m.primary ? Vec2d{0, 0} : Vec2d{-m.mid.x * m.T.kx + m.fine.x, -m.mid.y * m.T.ky + m.fine.y};
        m.cam = views_.views[m.index].camera;
        m.cam.scale = s[k];
        m.cam.cx = m.T.c.x + m.offset.x - s[k] * dot(mid, m.cam.r);
        m.cam.cy = m.T.c.y + m.offset.y + s[k] * dot(mid, m.cam.u);
    }
}

// A view following an anchor is placed where its silhouette overlaps the anchor's most
// along their shared lines of sight: along each axis by the overlap of the two profiles (the
// cells per row or column), then in whole and quarter cells about that.
void Reconciler::place_followers() {
    const ReconcileGrid g = grid(fine_cells_);
    for (std::size_t k = 0; k < members_.size(); ++k) {
        if (anchor_[k] == k) continue;
        Member& m = members_[k];
        const AxisMask a = mask_of(members_[anchor_[k]], g);
        auto iou = [&](const AxisMask& b) {
            double both = 0, either = 0;
            for (std::size_t i = 0; i < a.in.size(); ++i) both += a.in[i] & b.in[i], either += a.in[i] | b.in[i];
            return either > 0 ? both / either : 0.0;
        };
        m.fine = {0, 0};
        fit();
        const AxisMask b = mask_of(m, g);
        // Image pixels per cell along each world axis of the view, with the image's sense.
        const double sx = g.h[std::size_t(m.ar)] * m.cam.scale * m.cam.r[m.ar];
        const double sy = -g.h[std::size_t(m.au)] * m.cam.scale * m.cam.u[m.au];
        for (int axis : {m.ar, m.au}) {
            const int na = g.n[std::size_t(a.a)], n = g.n[std::size_t(axis)];
            std::vector<double> pa(std::size_t(n), 0.0), pb(std::size_t(n), 0.0);
            for (std::size_t i = 0; i < a.in.size(); ++i) {
                const int c = axis == a.a ? int(i % std::size_t(na)) : int(i / std::size_t(na));
                pa[std::size_t(c)] += a.in[i], pb[std::size_t(c)] += b.in[i];
            }
            int best_shift = 0;
            double best = -1;
            for (int d = -n / 3; d <= n / 3; ++d) {
                double o = 0;
                for (int i = 0; i < n; ++i)
                    if (i - d >= 0 && i - d < n) o += std::min(pa[std::size_t(i)], pb[std::size_t(i - d)]);
                if (o > best + 1e-9 || (std::abs(o - best) <= 1e-9 && std::abs(d) < std::abs(best_shift)))
                    best = o, best_shift = d;
            }
            if (axis == m.ar) m.fine.x += best_shift * sx;
            else m.fine.y += best_shift * sy;
        }
        Vec2d best = m.fine;
        fit();
        double best_iou = iou(mask_of(m, g));
        for (double step : {1.0, 0.25}) {
            const Vec2d centre = best;
            for (int j = -2; j <= 2; ++j)
                for (int i = -2; i <= 2; ++i) {
                    m.fine = {centre.x + i * step * std::abs(sx), centre.y + j * step * std::abs(sy)};
                    fit();
                    if (const double v = iou(mask_of(m, g)); v > best_iou) best_iou = v, best = m.fine;
                }
        }
        m.fine = best;
        fit();
    }
}

ReconcileGrid Reconciler::grid(int cells) const {
    if (span_set_) return ReconcileGrid::over(span_.first, span_.second - span_.first, cells);
    return ReconcileGrid::over({-size_[0] / 2, 0, -size_[2] / 2}, {size_[0], size_[1], size_[2]}, cells);
}

AxisMask Reconciler::mask_of(const Member& m, const ReconcileGrid& g) const {
    const View& v = views_.views[m.index];
    return sample_mask(g, std::min(m.ar, m.au), std::max(m.ar, m.au), [&](const Vec3d& p) {
        Vec2d q = m.cam.project(p);
        if (!m.applied) q = m.T.inv({q.x - m.offset.x, q.y - m.offset.y});
        return v.coverage.at(int(std::floor(q.x)), int(std::floor(q.y))) >= 0.5f;
    });
}

std::vector<AxisMask> Reconciler::member_masks(const ReconcileGrid& g) const {
    std::vector<AxisMask> out;
    for (const Member& m : members_) out.push_back(mask_of(m, g));
    return out;
}

std::vector<AxisMask> Reconciler::group_masks(const std::vector<AxisMask>& m, const std::string& mode) const {
    std::vector<AxisMask> out;
    for (const auto& g : groups_) {
        std::vector<const AxisMask*> ms;
        for (std::size_t k : g) ms.push_back(&m[k]);
        out.push_back(merge_masks(ms, mode.empty() ? opt_.opposite : mode));
    }
    return out;
}

std::vector<double> Reconciler::missing_shares(int cells) const {
    const ReconcileGrid g = grid(cells);
    const std::vector<AxisMask> m = member_masks(g), gm = group_masks(m);
    std::vector<const AxisMask*> all;
    for (const auto& x : gm) all.push_back(&x);
    std::vector<double> out;
    for (const AxisMask& own : m) {
        const auto miss = missing_cells(g, own, all);
        double in = 0, out_n = 0;
        for (std::size_t i = 0; i < own.in.size(); ++i) in += own.in[i], out_n += miss[i];
        out.push_back(in > 0 ? out_n / in : 0.0);
    }
    return out;
}

// What the turn search minimises: the drawings' shares the hull leaves out, and a little of
// the box the hull does not fill. Turns that make every drawing agree leave the hull as
// large as the drawings allow; a view turned against the others cuts it (a box drawn
// turned by 2 degrees, with every other view agreeing, has its edges cut but nothing of
// any drawing missing).
double Reconciler::score() const {
    const ReconcileGrid g = grid(search_cells_);
    const std::vector<AxisMask> m = member_masks(g), gm = group_masks(m, "union");
    std::vector<const AxisMask*> all;
    for (const auto& x : gm) all.push_back(&x);
    double s = 0;
    for (const AxisMask& own : m) {
        const auto miss = missing_cells(g, own, all);
        double in = 0, out = 0;
        for (std::size_t i = 0; i < own.in.size(); ++i) in += own.in[i], out += miss[i];
        s += in > 0 ? out / in : 0.0;
    }
    return s + 0.05 * (1.0 - hull_share(g, all));
}

// Each free view's turn in turn, the others held: coarse steps over the range, then fine
// ones about the best; a turn must buy a clear gain over none.
void Reconciler::search_turns() {
    for (int round = 0; round < 2; ++round)
        for (std::size_t k = 0; k < members_.size(); ++k) {
            Member& m = members_[k];
            if (m.primary || anchor_[k] != k) continue;
            auto eval = [&](double th) {
                m.T.theta = th;
                fit();
                return score();
            };
            const double none = eval(0.0);
            double best = none, best_th = 0.0;
            const double r = opt_.max_turn_deg * kDeg;
            for (double th = -r; th <= r + 1e-12; th += 0.5 * kDeg)
                if (const double s = eval(th); s < best) best = s, best_th = th;
            const double centre = best_th;
            for (double th = centre - 0.4 * kDeg; th <= centre + 0.4 * kDeg + 1e-12; th += 0.1 * kDeg)
                if (const double s = eval(th); s < best) best = s, best_th = th;
            m.T.theta = best < none - 0.002 ? best_th : 0.0;
            fit();
        }
}

bool Reconciler::moved(const Member& m) const {
    if (m.primary) return false;
    return std::abs(m.T.kx - 1) * m.w > 0.5 || std::abs(m.T.ky - 1) * m.h > 0.5 || m.T.theta != 0.0 ||
           std::abs(m.T.t.x) > 0.5 || std::abs(m.T.t.y) > 0.5;
}

// The silhouette and the drawing resampled through T, on a canvas grown where the stretched
// silhouette would leave it.
void Reconciler::resample(Member& m) {
    View& v = views_.views[m.index];
    const Coverage::Box& b = v.coverage.inside_box();
    double x0 = 0, y0 = 0, x1 = v.width, y1 = v.height;
    for (const Vec2d& p : {Vec2d{b.x0 - 2.0, b.y0 - 2.0}, Vec2d{b.x1 + 3.0, b.y0 - 2.0}, Vec2d{b.x0 - 2.0, b.y1 + 3.0},
                           Vec2d{b.x1 + 3.0, b.y1 + 3.0}}) {
        const Vec2d q = m.T.fwd(p);
        x0 = std::min(x0, q.x), y0 = std::min(y0, q.y), x1 = std::max(x1, q.x), y1 = std::max(y1, q.y);
    }
    const int left = int(std::ceil(-x0)), top = int(std::ceil(-y0));
    const int W = int(std::ceil(x1)) + left, H = int(std::ceil(y1)) + top;
    m.offset = {double(left), double(top)};
    m.cam.cx += left, m.cam.cy += top;
    std::vector<float> cov(std::size_t(W) * H, 0.0f);
    Image img{W, H, 4, std::vector<float>(std::size_t(W) * H * 4, 0.0f), {}};
    tbb::parallel_for(0, H, [&](int y) {
        for (int x = 0; x < W; ++x) {
            const Vec2d p = m.T.inv({x + 0.5 - left, y + 0.5 - top});
            cov[std::size_t(y) * W + x] = sample(v.coverage, p.x, p.y);
            const int ix = std::clamp(int(std::floor(p.x)), 0, v.width - 1),
                      iy = std::clamp(int(std::floor(p.y)), 0, v.height - 1);
            const auto px = v.image.rgba(std::size_t(iy) * v.width + ix);
            for (int c = 0; c < 4; ++c) img.pixels[(std::size_t(y) * W + x) * 4 + c] = px[std::size_t(c)];
        }
    });
    v.coverage = Coverage(cov, W, H);
    v.image = std::move(img);
    v.width = W, v.height = H;
}

// Views along one line of sight show one silhouette, mirrored: each takes the union (or the
// intersection, or the first's) of all of them, sampled along the shared lines of sight.
void Reconciler::merge_opposites() {
    for (const auto& g : groups_) {
        if (g.size() < 2) continue;
        std::vector<Coverage> before;
        for (std::size_t k : g) before.push_back(views_.views[members_[k].index].coverage);
        for (std::size_t a = 0; a < g.size(); ++a) {
            View& v = views_.views[members_[g[a]].index];
            const Camera& ca = members_[g[a]].cam;
            std::vector<float> cov(std::size_t(v.width) * v.height);
            tbb::parallel_for(0, v.height, [&](int y) {
                for (int x = 0; x < v.width; ++x) {
                    Vec3d o, d;
                    ca.ray(x + 0.5, y + 0.5, o, d);
                    float val = opt_.opposite == "primary" ? -1.0f : before[a].at(x, y);
                    for (std::size_t b = 0; b < g.size(); ++b) {
                        if (b == a && opt_.opposite != "primary") continue;
                        const Vec2d q = members_[g[b]].cam.project(o);
                        const float s = b == a ? before[a].at(x, y) : sample(before[b], q.x, q.y);
                        if (opt_.opposite == "primary") {
                            val = s;
                            break;
                        }
                        val = opt_.opposite == "union" ? std::max(val, s) : std::min(val, s);
                    }
                    cov[std::size_t(y) * v.width + x] = val;
                }
            });
            v.coverage = Coverage(cov, v.width, v.height);
        }
    }
}

std::vector<ViewReconciliation> Reconciler::run() {
    std::vector<ViewReconciliation> out(views_.views.size());
    for (std::size_t i = 0; i < out.size(); ++i) out[i].name = views_.views[i].name;
    setup();
    if (members_.size() < 2) return out;
    fit();
    search_turns();
    place_followers();
    bool change = std::any_of(groups_.begin(), groups_.end(), [](const auto& g) { return g.size() > 1; });
    for (const Member& m : members_) change = change || moved(m);
    std::vector<double> shares = missing_shares(fine_cells_);
    change = change || *std::max_element(shares.begin(), shares.end()) > 0.002;
    if (change) {
        for (Member& m : members_) {
            if (moved(m)) resample(m);
            m.applied = true;
            views_.views[m.index].camera = m.cam;
        }
        views_.bounds_min = {-size_[0] / 2, 0.0, -size_[2] / 2};
        views_.bounds_max = {size_[0] / 2, size_[1], size_[2] / 2};
        views_.has_bounds = true;
        span_ = silhouette_span(true), span_set_ = true;
        // Bent on the drawings as they are, before merging: what an opposite view alone
        // draws is not a disagreement to bend away (intersect removes it on purpose).
        bend();
        merge_opposites();
        shares = missing_shares(fine_cells_);
        settle_box();
    }
    double primary_scale = views_.views[std::min(opt_.primary, views_.views.size() - 1)].camera.scale;
    for (const Member& m : members_)
        if (m.primary) primary_scale = m.cam.scale;
    for (std::size_t k = 0; k < members_.size(); ++k) {
        const Member& m = members_[k];
        ViewReconciliation& r = out[m.index];
        r.reconciled = true;
        // The drawing's scale along each axis against the primary's.
        if (change)
            r.scale_x = m.T.kx * primary_scale / m.cam.scale, r.scale_y = m.T.ky * primary_scale / m.cam.scale,
            r.turn_deg = -m.T.theta / kDeg;
        r.warp_px = warp_px_[k];
        r.missing_pct = 100.0 * shares[k];
        if (change) warn_moved(m, r);
    }
    return out;
}

} // namespace reconcile_detail

std::vector<ViewReconciliation> reconcile_views(Views& views, const ReconcileOptions& opt,
                                                std::vector<std::string>& warnings) {
    return reconcile_detail::Reconciler(views, opt, warnings).run();
}

} // namespace cm
