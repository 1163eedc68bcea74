#include "align.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
#include <iomanip>
#include <limits>
#include <sstream>

#include <tbb/parallel_for.h>

#include "core/error.h"
#include "silhouette_extent.h"

namespace cm {

int axis_of(const Vec3d& a) {
    for (int k = 0; k < 3; ++k)
        if (std::abs(std::abs(a[k]) - 1.0) < 1e-9) return k;
    return -1;
}

namespace {

const char* axis_name(int k) { return k == 0 ? "width (X)" : k == 1 ? "height (Y)" : "depth (Z)"; }

bool axis_view(const Camera& c) { return c.orthographic() && axis_of(c.r) >= 0 && axis_of(c.u) >= 0; }

// An oblique view shares no axis with the others, so its placement cannot come from extents.
// The axis views (already aligned) carve a visual hull of the object, which holds the object:
// at the right placement the silhouette lies inside the hull's projection. The view is
// placed at the centre of the placements that keep the silhouette's boundary inside the
// projection, searched around the one that matches centroids. Its scale stays the first
// view's (a turnaround is drawn at one scale).
void place_oblique_views(Views& views, const std::vector<bool>& fixed) {
    std::vector<const View*> axis;
    for (const auto& v : views.views)
        if (axis_view(v.camera)) axis.push_back(&v);
    if (axis.empty()) return;
    const Vec3d lo = views.bounds_min, hi = views.bounds_max, ext = hi - lo;
    const double longest = std::max({ext.x, ext.y, ext.z});
    if (!(longest > 0)) return;
    for (std::size_t vi = 0; vi < views.views.size(); ++vi) {
        View& v = views.views[vi];
        Camera& c = v.camera;
        if (!c.orthographic() || axis_view(c) || fixed[vi]) continue;
        // Hull cells of about 2 px in this view (at most 200 along the longest side).
        const int n = std::clamp(int(std::ceil(longest * c.scale / 2.0)), 16, 200);
        const double h = longest / n;
        const int nx = std::max(1, int(std::ceil(ext.x / h))), ny = std::max(1, int(std::ceil(ext.y / h))),
                  nz = std::max(1, int(std::ceil(ext.z / h)));
        const Vec3d cell{ext.x / nx, ext.y / ny, ext.z / nz};
        std::vector<Vec2d> q;
        for (int k = 0; k < nz; ++k)
            for (int j = 0; j < ny; ++j)
                for (int i = 0; i < nx; ++i) {
                    const Vec3d p{lo.x + (i + 0.5) * cell.x, lo.y + (j + 0.5) * cell.y, lo.z + (k + 0.5) * cell.z};
                    bool inside = true;
                    for (const View* a : axis) {
                        const Vec2d pa = a->camera.project(p);
                        if (!a->inside(int(std::floor(pa.x)), int(std::floor(pa.y)))) {
                            inside = false;
                            break;
                        }
                    }
                    if (inside) q.push_back({c.scale * dot(p, c.r), -c.scale * dot(p, c.u)});
                }
        if (q.empty()) continue;
        // The hull's projection (origin at 0): each cell's footprint as its bounding rectangle.
        const double ax =
            0.5 * c.scale * (std::abs(c.r.x) * cell.x + std::abs(c.r.y) * cell.y + std::abs(c.r.z) * cell.z);
        const double ay =
            0.5 * c.scale * (std::abs(c.u.x) * cell.x + std::abs(c.u.y) * cell.y + std::abs(c.u.z) * cell.z);
        double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
        for (const Vec2d& p : q) {
            x0 = std::min(x0, p.x - ax), x1 = std::max(x1, p.x + ax);
            y0 = std::min(y0, p.y - ay), y1 = std::max(y1, p.y + ay);
        }
        const int W = int(std::ceil(x1 - x0)) + 2, H = int(std::ceil(y1 - y0)) + 2;
        if (double(W) * H > 64e6) continue; // absurd scale; keep the first guess
        std::vector<char> mask(std::size_t(W) * H, 0);
        for (const Vec2d& p : q) {
            const int i0 = int(std::ceil(p.x - ax - x0 - 0.5)), i1 = int(std::floor(p.x + ax - x0 - 0.5));
            const int j0 = int(std::ceil(p.y - ay - y0 - 0.5)), j1 = int(std::floor(p.y + ay - y0 - 0.5));
            for (int jj = std::max(0, j0); jj <= std::min(H - 1, j1); ++jj)
                for (int ii = std::max(0, i0); ii <= std::min(W - 1, i1); ++ii) mask[std::size_t(jj) * W + ii] = 1;
        }
        double hx = 0, hy = 0, hn = 0;
        for (int jj = 0; jj < H; ++jj)
            for (int ii = 0; ii < W; ++ii)
                if (mask[std::size_t(jj) * W + ii]) hx += ii + 0.5 + x0, hy += jj + 0.5 + y0, ++hn;
        double sx = 0, sy = 0, sn = 0;
        std::vector<Vec2d> boundary;
        for (int y = 0; y < v.height; ++y)
            for (int x = 0; x < v.width; ++x)
                if (v.inside(x, y)) {
                    sx += x + 0.5, sy += y + 0.5, ++sn;
                    if (!v.inside(x - 1, y) || !v.inside(x + 1, y) || !v.inside(x, y - 1) || !v.inside(x, y + 1))
                        boundary.push_back({x + 0.5, y + 0.5});
                }
        if (hn == 0 || sn == 0) continue;
        // Image point of the world origin when the centroids match.
        const double tx = sx / sn - hx / hn, ty = sy / sn - hy / hn;
        const int R = std::max(4, int(0.03 * std::max(W, H)));
        std::vector<std::size_t> outside(std::size_t(2 * R + 1) * (2 * R + 1), 0);
        std::size_t best = std::numeric_limits<std::size_t>::max();
        for (int dy = -R; dy <= R; ++dy)
            for (int dx = -R; dx <= R; ++dx) {
                std::size_t count = 0;
                for (const Vec2d& b : boundary) {
                    const int ii = int(std::floor(b.x - (tx + dx) - x0)), jj = int(std::floor(b.y - (ty + dy) - y0));
                    count += ii < 0 || jj < 0 || ii >= W || jj >= H || !mask[std::size_t(jj) * W + ii];
                }
                outside[std::size_t(dy + R) * (2 * R + 1) + std::size_t(dx + R)] = count;
                best = std::min(best, count);
            }
        const std::size_t slack = std::max<std::size_t>(2, boundary.size() / 500);
        double mx = 0, my = 0, mn = 0;
        for (int dy = -R; dy <= R; ++dy)
            for (int dx = -R; dx <= R; ++dx)
                if (outside[std::size_t(dy + R) * (2 * R + 1) + std::size_t(dx + R)] <= best + slack)
                    mx += dx, my += dy, ++mn;
        c.cx = tx + mx / mn;
        c.cy = ty + my / mn;
    }
}

void warn_once(std::vector<std::string>& warnings, const std::string& msg) {
    if (std::find(warnings.begin(), warnings.end(), msg) == warnings.end()) warnings.push_back(msg);
}

// No camera fixed: the first view sets the unit, the silhouettes everything else, and the
// world is the output frame (pivot at the bottom centre of the box they imply).
void align_from_silhouettes(Views& views, const AlignOptions& opt, const std::vector<Extent>& ext,
                            std::vector<std::string>& warnings) {
    const std::size_t n = views.views.size();
    // World extent of each axis in units of the first view's pixels, and who measured it.
    std::array<double, 3> size{-1, -1, -1};
    std::array<std::string, 3> measured_by;
    std::vector<double> scale(n, -1.0);
    auto axes = [&](std::size_t i, int& ar, int& au, double& wr, double& hu) {
        const Camera& c = views.views[i].camera;
        ar = axis_of(c.r);
        au = axis_of(c.u);
        wr = ext[i].x1 - ext[i].x0;
        hu = ext[i].y1 - ext[i].y0;
    };
    // The first view fixes the unit; then propagate through shared axes until nothing changes.
    scale[0] = 1.0;
    bool changed = true;
    while (changed) {
        changed = false;
        for (std::size_t i = 0; i < n; ++i) {
            int ar, au;
            double wr, hu;
            axes(i, ar, au, wr, hu);
            if (scale[i] < 0) {
                if (ar >= 0 && size[ar] > 0) scale[i] = wr / size[ar];
                else if (au >= 0 && size[au] > 0) scale[i] = hu / size[au];
                else continue;
                changed = true;
            }
            auto record = [&](int a, double pix) {
                if (a < 0) return;
                const double world = pix / scale[i];
                if (size[a] < 0) {
                    size[a] = world;
                    measured_by[a] = views.views[i].name;
                    changed = true;
                } else if (std::abs(world - size[a]) > opt.tolerance * size[a]) {
                    std::ostringstream os;
                    os.precision(3);
                    os << "views \"" << measured_by[a] << "\" and \"" << views.views[i].name << "\" disagree on the "
                       << axis_name(a) << ": " << size[a] << " against " << world << " units ("
                       << 100.0 * std::abs(world - size[a]) / size[a] << "% apart)";
                    warn_once(warnings, os.str());
                }
            };
            record(ar, wr);
            record(au, hu);
        }
    }
    for (std::size_t i = 0; i < n; ++i)
        if (scale[i] < 0) scale[i] = 1.0; // shares no axis (e.g. an oblique view): same scale as the first
    // Each axis is usually measured by two views: use all measurements. Alternate between the
    // sizes (mean over the views measuring an axis) and the scales of all views but the first
    // (geometric mean over their axes), in the log domain a least-squares fit.
    for (int iter = 0; iter < 8; ++iter) {
        std::array<double, 3> sum{0, 0, 0}, cnt{0, 0, 0};
        for (std::size_t i = 0; i < n; ++i) {
            int ar, au;
            double wr, hu;
            axes(i, ar, au, wr, hu);
            if (ar >= 0) sum[std::size_t(ar)] += wr / scale[i], ++cnt[std::size_t(ar)];
            if (au >= 0) sum[std::size_t(au)] += hu / scale[i], ++cnt[std::size_t(au)];
        }
        for (int k = 0; k < 3; ++k)
            if (cnt[std::size_t(k)] > 0) size[std::size_t(k)] = sum[std::size_t(k)] / cnt[std::size_t(k)];
        for (std::size_t i = 1; i < n; ++i) {
            int ar, au;
            double wr, hu;
            axes(i, ar, au, wr, hu);
            double lsum = 0, lcnt = 0;
            if (ar >= 0) lsum += std::log(wr / size[std::size_t(ar)]), ++lcnt;
            if (au >= 0) lsum += std::log(hu / size[std::size_t(au)]), ++lcnt;
            if (lcnt > 0) scale[i] = std::exp(lsum / lcnt);
        }
    }
    for (int k = 0; k < 3; ++k)
        if (size[k] < 0) {
            // No view measured this axis: use the largest known extent so the box still holds the object.
            size[k] = std::max({size[0], size[1], size[2], 1.0});
        }
    // Real size: rescale world units.
    double units = 1.0;
    if (opt.height) units = *opt.height / size[1];
    else if (opt.width) units = *opt.width / size[0];
    else if (opt.depth) units = *opt.depth / size[2];
    for (auto& s : size) s *= units;
    views.units_per_pixel = units;

    views.bounds_min = {-size[0] / 2, 0.0, -size[2] / 2};
    views.bounds_max = {size[0] / 2, size[1], size[2] / 2};
    views.has_bounds = true;
    for (std::size_t i = 0; i < n; ++i) {
        Camera& c = views.views[i].camera;
        c.scale = scale[i] / units;
        // The box's centre onto the silhouette's centre (an axis view's extents are the box's
        // projection; an oblique view's are a first guess, refined below).
        const Vec3d mid = (views.bounds_min + views.bounds_max) * 0.5;
        c.cx = 0.5 * (ext[i].x0 + ext[i].x1) - c.scale * dot(mid, c.r);
        c.cy = 0.5 * (ext[i].y0 + ext[i].y1) + c.scale * dot(mid, c.u);
    }
}

// The world interval along one axis that a silhouette covers under its view's camera, from
// its extent along image x (`along_u` false: the axis of r) or image y (true: the axis of u).
struct Span {
    int axis = -1;
    double lo = 0, hi = 0;
};

Span span_of(const Camera& c, const Extent& e, bool along_u) {
    Span sp;
    const Vec3d& dir = along_u ? c.u : c.r;
    sp.axis = axis_of(dir);
    if (sp.axis < 0) return sp;
    // p . r = (x - cx) / s;  p . u = (cy - y) / s.
    const double a = along_u ? (c.cy - e.y1) / c.scale : (e.x0 - c.cx) / c.scale;
    const double b = along_u ? (c.cy - e.y0) / c.scale : (e.x1 - c.cx) / c.scale;
    if (dir[sp.axis] > 0) sp.lo = a, sp.hi = b;
    else sp.lo = -b, sp.hi = -a;
    return sp;
}

// Some cameras fixed: the world is theirs. They measure the axes they see; the other views
// take their scale from the axes they share with what is measured, and their placement from
// the box; an axis nobody fixed measures is centred on 0 (the height stands on Y = 0).
// The steps, in order: measure the fixed views' axes, scale the other axis views, size the
// axes no view measured, place the other views, set the box.
class FixedCameraAlignment {
public:
    FixedCameraAlignment(Views& views, const AlignOptions& opt, const std::vector<Extent>& ext,
                         const std::vector<bool>& fixed, std::vector<std::string>& warnings)
        : views_(views), opt_(opt), ext_(ext), fixed_(fixed), warnings_(warnings), n_(views.views.size()) {}

    void run() {
        measure_fixed_axes();
        scale_axis_views();
        size_unmeasured_axes();
        place_other_views();
        set_bounds();
    }

private:
    void set_axis(int k, double size, const std::string& by) {
        lo_[std::size_t(k)] = k == 1 ? 0.0 : -size / 2;
        hi_[std::size_t(k)] = k == 1 ? size : size / 2;
        known_[std::size_t(k)] = true;
        measured_by_[std::size_t(k)] = by;
    }

    // The fixed views measure their axes directly: the mean of their spans, and a warning
    // where two of them place or size an axis differently.
    void measure_fixed_axes() {
        std::array<std::vector<std::pair<Span, std::size_t>>, 3> spans;
        for (std::size_t i = 0; i < n_; ++i) {
            if (!fixed_[i]) continue;
            const Camera& c = views_.views[i].camera;
            if (first_fixed_scale_ == 0) first_fixed_scale_ = c.scale;
            for (bool along_u : {false, true}) {
                const Span sp = span_of(c, ext_[i], along_u);
                if (sp.axis >= 0) spans[std::size_t(sp.axis)].push_back({sp, i});
            }
        }
        for (int k = 0; k < 3; ++k) {
            const auto& sk = spans[std::size_t(k)];
            if (sk.empty()) continue;
            double l = 0, h = 0;
            for (const auto& [sp, i] : sk) l += sp.lo, h += sp.hi;
            lo_[std::size_t(k)] = l / double(sk.size());
            hi_[std::size_t(k)] = h / double(sk.size());
            known_[std::size_t(k)] = true;
            measured_by_[std::size_t(k)] = views_.views[sk.front().second].name;
            warn_fixed_disagreements(k, sk);
        }
    }

    void warn_fixed_disagreements(int k, const std::vector<std::pair<Span, std::size_t>>& sk) {
        const double size = hi_[std::size_t(k)] - lo_[std::size_t(k)];
        for (std::size_t a = 0; a < sk.size(); ++a)
            for (std::size_t b = a + 1; b < sk.size(); ++b) {
                const Span &p = sk[a].first, &q = sk[b].first;
                const double apart = std::max(std::abs(p.lo - q.lo), std::abs(p.hi - q.hi));
                if (!(apart > opt_.tolerance * size)) continue;
                std::ostringstream os;
                os.precision(4);
                os << "views \"" << views_.views[sk[a].second].name << "\" and \"" << views_.views[sk[b].second].name
                   << "\" disagree on the " << axis_name(k) << " under their fixed cameras: " << p.lo << " to " << p.hi
                   << " against " << q.lo << " to " << q.hi << " units (" << std::setprecision(3)
                   << 100.0 * apart / size << "% of the size apart)";
                warn_once(warnings_, os.str());
            }
    }

    // The other axis views: scale from the measured axes they see (in the log domain, the
    // mean over both when both are measured); an axis only they see is measured by them.
    void scale_axis_views() {
        scale_.assign(n_, -1.0);
        for (std::size_t i = 0; i < n_; ++i)
            if (fixed_[i]) scale_[i] = views_.views[i].camera.scale;
        for (;;) {
            if (scale_from_measured_axes()) continue;
            // An axis view that shares no measured axis (only oblique views are fixed): drawn
            // at the first fixed view's scale.
            std::size_t next = n_;
            for (std::size_t i = 0; i < n_ && next == n_; ++i)
                if (scale_[i] < 0 && axis_view(views_.views[i].camera)) next = i;
            if (next == n_) break;
            scale_[next] = first_fixed_scale_;
            const Camera& c = views_.views[next].camera;
            set_axis(axis_of(c.r), (ext_[next].x1 - ext_[next].x0) / scale_[next], views_.views[next].name);
            set_axis(axis_of(c.u), (ext_[next].y1 - ext_[next].y0) / scale_[next], views_.views[next].name);
        }
    }

    // One pass over the axis views without a scale; true when one got its scale.
    bool scale_from_measured_axes() {
        bool changed = false;
        for (std::size_t i = 0; i < n_; ++i) {
            const View& v = views_.views[i];
            if (scale_[i] > 0 || !axis_view(v.camera)) continue;
            const int ar = axis_of(v.camera.r), au = axis_of(v.camera.u);
            const double wr = ext_[i].x1 - ext_[i].x0, hu = ext_[i].y1 - ext_[i].y0;
            double lsum = 0, lcnt = 0;
            if (known_[std::size_t(ar)]) lsum += std::log(wr / (hi_[std::size_t(ar)] - lo_[std::size_t(ar)])), ++lcnt;
            if (known_[std::size_t(au)]) lsum += std::log(hu / (hi_[std::size_t(au)] - lo_[std::size_t(au)])), ++lcnt;
            if (lcnt == 0) continue;
            scale_[i] = std::exp(lsum / lcnt);
            changed = true;
            for (const auto& [a, pix] : {std::pair{ar, wr}, std::pair{au, hu}}) {
                const double world = pix / scale_[i];
                if (!known_[std::size_t(a)]) {
                    set_axis(a, world, v.name);
                    continue;
                }
                const double size = hi_[std::size_t(a)] - lo_[std::size_t(a)];
                if (std::abs(world - size) > opt_.tolerance * size) {
                    std::ostringstream os;
                    os.precision(3);
                    os << "views \"" << measured_by_[std::size_t(a)] << "\" and \"" << v.name << "\" disagree on the "
                       << axis_name(a) << ": " << size << " against " << world << " units ("
                       << 100.0 * std::abs(world - size) / size << "% apart)";
                    warn_once(warnings_, os.str());
                }
            }
        }
        return changed;
    }

    // An axis no view measured: as long as the longest, so the box still holds the object.
    void size_unmeasured_axes() {
        double longest = 0;
        for (std::size_t k = 0; k < 3; ++k)
            if (known_[k]) longest = std::max(longest, hi_[k] - lo_[k]);
        if (!(longest > 0)) longest = 1.0 / first_fixed_scale_;
        for (int k = 0; k < 3; ++k)
            if (!known_[std::size_t(k)]) set_axis(k, longest, "");
    }

    // The other views: the box's centre onto the silhouette's centre (an oblique view's
    // placement is refined afterwards), at the first fixed view's scale when they share no axis.
    void place_other_views() {
        const Vec3d mid{0.5 * (lo_[0] + hi_[0]), 0.5 * (lo_[1] + hi_[1]), 0.5 * (lo_[2] + hi_[2])};
        for (std::size_t i = 0; i < n_; ++i) {
            if (fixed_[i]) continue;
            Camera& c = views_.views[i].camera;
            c.scale = scale_[i] > 0 ? scale_[i] : first_fixed_scale_;
            c.cx = 0.5 * (ext_[i].x0 + ext_[i].x1) - c.scale * dot(mid, c.r);
            c.cy = 0.5 * (ext_[i].y0 + ext_[i].y1) + c.scale * dot(mid, c.u);
        }
    }

    // The box: the manifest's when it gives one, else the one the silhouettes imply.
    void set_bounds() {
        views_.has_bounds = true;
        if (opt_.bounds) {
            const auto& b = *opt_.bounds;
            views_.bounds_min = {b[0], b[1], b[2]};
            views_.bounds_max = {b[3], b[4], b[5]};
        } else {
            views_.bounds_min = {lo_[0], lo_[1], lo_[2]};
            views_.bounds_max = {hi_[0], hi_[1], hi_[2]};
        }
        views_.units_per_pixel = 1.0 / views_.views.front().camera.scale;
    }

    Views& views_;
    const AlignOptions& opt_;
    const std::vector<Extent>& ext_;
    const std::vector<bool>& fixed_;
    std::vector<std::string>& warnings_;
    const std::size_t n_;
    std::array<double, 3> lo_{0, 0, 0}, hi_{0, 0, 0}; ///< the box, per axis
    std::array<bool, 3> known_{false, false, false};  ///< axes measured (or sized) so far
    std::array<std::string, 3> measured_by_;          ///< the view that measured each axis
    double first_fixed_scale_ = 0;
    std::vector<double> scale_; ///< per view; < 0: not known yet
};

} // namespace

void align_views(Views& views, const AlignOptions& opt, std::vector<std::string>& warnings) {
    const std::size_t n = views.views.size();
    // Each view's extent on its own, side by side; the first failing view in order is
    // reported, whichever thread found it first.
    std::vector<Extent> ext(n);
    std::vector<std::string> errors(n);
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
        try {
            ext[i] = silhouette_extent(views.views[i]);
        } catch (const std::exception& e) {
            errors[i] = e.what();
        }
    });
    for (const auto& e : errors)
        if (!e.empty()) throw Error(e);
    std::vector<bool> fixed(n, false);
    for (std::size_t i = 0; i < n && i < opt.fixed.size(); ++i)
        fixed[i] = opt.fixed[i] && views.views[i].camera.orthographic();
    if (std::find(fixed.begin(), fixed.end(), true) == fixed.end()) {
        if (opt.bounds) throw Error("a box (bounds) for drawn views needs fixed cameras (scale and origin)");
        align_from_silhouettes(views, opt, ext, warnings);
    } else {
        if (opt.height || opt.width || opt.depth)
            throw Error(
                "a real size (height, width or depth) cannot go with fixed cameras (scale, origin): they set the "
                "units");
        FixedCameraAlignment(views, opt, ext, fixed, warnings).run();
    }
    place_oblique_views(views, fixed);
}

} // namespace cm
