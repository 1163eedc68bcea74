#include "geometry/silhouette_field.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/error.h"

namespace cm {

SilhouetteField::Table SilhouetteField::summed_area(const View& view) {
    const int w = view.width, h = view.height;
    Table sat;
    if (w <= 0 || h <= 0 || view.coverage.size() != std::size_t(w) * std::size_t(h)) return sat;
    sat.width = w;
    sat.height = h;
    const Coverage& cov = view.coverage;
    if (const Coverage::Box box = cov.inside_box(); !box.empty()) {
        sat.box_x = box.x0;
        sat.box_y = box.y0;
        sat.box_w = box.x1 - box.x0 + 1;
        sat.box_h = box.y1 - box.y0 + 1;
    }
    const int bw = sat.box_w, bh = sat.box_h;
    const std::size_t stride = std::size_t(bw) + 1;
    sat.counts.resize(stride * (std::size_t(bh) + 1)); // every entry is written below
    std::fill(sat.counts.begin(), sat.counts.begin() + std::ptrdiff_t(stride), 0u);
    // Each row's running count on its own (rows side by side), then the rows added down,
    // columns side by side in strips: the same integers as one pass row after row.
    tbb::parallel_for(tbb::blocked_range<int>(0, bh, 64), [&](const tbb::blocked_range<int>& r) {
        for (int j = r.begin(); j != r.end(); ++j) {
            std::uint32_t* out = sat.counts.data() + std::size_t(j + 1) * stride;
            // (the box lies within the coverage's window)
            const float* c = cov.window_row(sat.box_y + j) + (sat.box_x - cov.x0());
            std::uint32_t row = 0;
            out[0] = 0;
            for (int i = 0; i < bw; ++i) {
                row += c[i] >= 0.5f ? 1u : 0u;
                out[i + 1] = row;
            }
        }
    });
    constexpr std::size_t kStrip = 1024; // columns per task: 4 KB of each row
    tbb::parallel_for(tbb::blocked_range<std::size_t>(1, stride, kStrip),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (int j = 1; j < bh; ++j) {
                              const std::uint32_t* above = sat.counts.data() + std::size_t(j) * stride;
                              std::uint32_t* out = sat.counts.data() + std::size_t(j + 1) * stride;
                              for (std::size_t i = r.begin(); i != r.end(); ++i) out[i] += above[i];
                          }
                      });
    return sat;
}

SilhouetteField::SilhouetteField(const View& view)
    : SilhouetteField(view, std::make_shared<const Table>(summed_area(view))) {}

SilhouetteField::SilhouetteField(const View& view, std::shared_ptr<const Table> table)
    : view_(&view), cov_(&view.coverage), w_(view.width), h_(view.height), sat_(std::move(table)) {
    if (w_ <= 0 || h_ <= 0 || view.coverage.size() != std::size_t(w_) * std::size_t(h_))
        throw Error("view \"" + view.name + "\" has no silhouette (coverage size does not match " + std::to_string(w_) +
                    "x" + std::to_string(h_) + ")");
    const Camera& c = view.camera;
    if (c.orthographic()) {
        // x = cx + s (p . r), y = cy - s (p . u)
        m_ = {c.scale * c.r.x,
              c.scale * c.r.y,
              c.scale * c.r.z,
              c.cx,
              -c.scale * c.u.x,
              -c.scale * c.u.y,
              -c.scale * c.u.z,
              c.cy,
              0,
              0,
              0,
              1};
        if (!(c.scale > 0) || !std::isfinite(c.scale))
            throw Error("view \"" + view.name + "\": the camera's scale (" + std::to_string(c.scale) +
                        ") is not a positive finite number of pixels per unit");
        for (double x : {c.cx, c.cy, c.r.x, c.r.y, c.r.z, c.u.x, c.u.y, c.u.z})
            if (!std::isfinite(x))
                throw Error("view \"" + view.name +
                            "\": the camera's origin or direction is not finite (NaN or "
                            "infinite angle or origin)");
        for (int a = 0; a < 3; ++a)
            if (m_[a] == 0 && m_[4 + a] == 0) drop_axis_ = a;
    } else {
        m_ = c.P;
        // Normalise so that points in front of the camera have positive w.
        const double det = m_[0] * (m_[5] * m_[10] - m_[6] * m_[9]) - m_[1] * (m_[4] * m_[10] - m_[6] * m_[8]) +
                           m_[2] * (m_[4] * m_[9] - m_[5] * m_[8]);
        for (double x : m_)
            if (!std::isfinite(x))
                throw Error("view \"" + view.name + "\": the camera matrix has an entry that is not a finite number");
        if (det == 0 || !std::isfinite(det)) throw Error("view \"" + view.name + "\" has a singular camera matrix");
        if (det < 0)
            for (double& v : m_) v = -v;
    }
    if (!sat_ || !sat_->of(w_, h_))
        throw Error("view \"" + view.name + "\": its summed-area table is not of its silhouette");
}

double SilhouetteField::coverage(double x, double y) const {
    double u = std::clamp(x - 0.5, -2.0, double(w_) + 1.0);
    double v = std::clamp(y - 0.5, -2.0, double(h_) + 1.0);
    const double fi = std::floor(u), fj = std::floor(v);
    const int i = int(fi), j = int(fj);
    const double a = u - fi, b = v - fj;
    const double c00 = pix(i, j), c10 = pix(i + 1, j), c01 = pix(i, j + 1), c11 = pix(i + 1, j + 1);
    return (c00 * (1 - a) + c10 * a) * (1 - b) + (c01 * (1 - a) + c11 * a) * b;
}

SilhouetteField::Class SilhouetteField::classify_rect(double x0, double y0, double x1, double y1) const {
    // Pixels whose centres span the rectangle (the bilinear support), clamped to the image.
    auto lo = [](double v, int n) {
        return std::clamp(int(std::floor(std::clamp(v - 0.5, -4.0, double(n) + 4.0))), 0, n - 1);
    };
    auto hi = [](double v, int n) {
        return std::clamp(int(std::floor(std::clamp(v - 0.5, -4.0, double(n) + 4.0))) + 1, 0, n - 1);
    };
    const int i0 = lo(x0, w_), i1 = hi(x1, w_), j0 = lo(y0, h_), j1 = hi(y1, h_);
    const Table& sat = *sat_;
    const std::uint32_t n = sat.at(i1 + 1, j1 + 1) - sat.at(i1 + 1, j0) - sat.at(i0, j1 + 1) + sat.at(i0, j0);
    if (n == 0) return Outside;
    if (n == std::uint32_t(i1 - i0 + 1) * std::uint32_t(j1 - j0 + 1)) return Inside;
    return Mixed;
}

SilhouetteField::Class SilhouetteField::classify_box(const Vec3d& lo, const Vec3d& hi) const {
    double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
    int behind = 0;
    for (int k = 0; k < 8; ++k) {
        const Vec3d p{(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z};
        const auto h = project_h(p);
        if (h[2] <= kMinDepth) {
            ++behind;
            continue;
        }
        const double x = h[0] / h[2], y = h[1] / h[2];
        x0 = std::min(x0, x), x1 = std::max(x1, x);
        y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
    if (behind == 8) return Outside;
    if (behind) return Mixed;
    return classify_rect(x0, y0, x1, y1);
}

SilhouetteField::Class SilhouetteField::classify_segment(const Vec3d& a, const Vec3d& b) const {
    const auto ha = project_h(a), hb = project_h(b);
    const bool ba = ha[2] <= kMinDepth, bb = hb[2] <= kMinDepth;
    if (ba && bb) return Outside;
    if (ba || bb) return Mixed;
    const double xa = ha[0] / ha[2], ya = ha[1] / ha[2], xb = hb[0] / hb[2], yb = hb[1] / hb[2];
    return classify_rect(std::min(xa, xb), std::min(ya, yb), std::max(xa, xb), std::max(ya, yb));
}

namespace {

// Root of q0 + q1 s + q2 s^2 in [lo, hi], where the polynomial is monotone and changes sign.
double monotone_root(double q0, double q1, double q2, double lo, double hi) {
    auto g = [&](double s) { return q0 + s * (q1 + s * q2); };
    double r = std::numeric_limits<double>::quiet_NaN();
    const double scale = std::abs(q0) + std::abs(q1) + std::abs(q2);
    if (std::abs(q2) <= 1e-14 * scale) {
        if (q1 != 0) r = -q0 / q1;
    } else {
        const double disc = q1 * q1 - 4 * q2 * q0;
        if (disc >= 0) {
            const double sq = std::sqrt(disc);
            const double qq = -0.5 * (q1 + (q1 >= 0 ? sq : -sq));
            const double r1 = qq / q2;
            const double r2 = qq != 0 ? q0 / qq : r1;
            const double tol = 1e-9 * (hi - lo) + 1e-15;
            if (r1 >= lo - tol && r1 <= hi + tol) r = r1;
            else if (r2 >= lo - tol && r2 <= hi + tol) r = r2;
        }
    }
    if (std::isfinite(r) && r >= lo - 1e-9 && r <= hi + 1e-9) return std::clamp(r, lo, hi);
    // Numerical corner: bisect.
    double a = lo, b = hi;
    const bool sa = g(a) >= 0;
    for (int it = 0; it < 60; ++it) {
        const double m = 0.5 * (a + b);
        if ((g(m) >= 0) == sa) a = m;
        else b = m;
    }
    return 0.5 * (a + b);
}

} // namespace

int SilhouetteField::transitions_2d(double x0, double y0, double x1, double y1, bool cur, double* flips,
                                    int max_flips) const {
    int n = 0;
    auto push = [&](double s) {
        if (n < max_flips) flips[n++] = s;
    };
    const double u0 = x0 - 0.5, v0 = y0 - 0.5, du = x1 - x0, dv = y1 - y0;
    // Breakpoints where u or v crosses an integer inside the part of the plane where the
    // interpolant varies ([0, w-1] x [0, h-1]); beyond it the clamped pixels are constant.
    // Integers strictly between p0 and p0 + d, clipped to [0, nmax - 1], in the order met.
    auto range = [](double p0, double d, int nmax, int& k, int& k_end) {
        if (d == 0) {
            k = 1, k_end = 0;
            return;
        }
        const double a = std::min(p0, p0 + d), b = std::max(p0, p0 + d);
        const int lo = std::max(int(std::floor(std::clamp(a, -2.0, double(nmax) + 2.0))) + 1, 0);
        const int hi = std::min(int(std::ceil(std::clamp(b, -2.0, double(nmax) + 2.0))) - 1, nmax - 1);
        if (d > 0) k = lo, k_end = hi;
        else k = hi, k_end = lo;
    };
    int ku, ku_end, kv, kv_end;
    range(u0, du, w_, ku, ku_end);
    range(v0, dv, h_, kv, kv_end);
    const int su = du > 0 ? 1 : -1, sv = dv > 0 ? 1 : -1;
    auto u_left = [&]() { return du != 0 && (su > 0 ? ku <= ku_end : ku >= ku_end); };
    auto v_left = [&]() { return dv != 0 && (sv > 0 ? kv <= kv_end : kv >= kv_end); };

    double s_prev = 0;
    for (;;) {
        const double s_u = u_left() ? (ku - u0) / du : 2.0;
        const double s_v = v_left() ? (kv - v0) / dv : 2.0;
        double s_next = std::min({s_u, s_v, 1.0});
        const bool take_u = s_u <= s_next, take_v = s_v <= s_next;
        s_next = std::clamp(s_next, s_prev, 1.0);
        if (s_next > s_prev) {
            // One cell of pixel centres over [s_prev, s_next].
            const double sm = 0.5 * (s_prev + s_next);
            const double fi = std::floor(std::clamp(u0 + du * sm, -2.0, double(w_) + 1.0));
            const double fj = std::floor(std::clamp(v0 + dv * sm, -2.0, double(h_) + 1.0));
            const int i = int(fi), j = int(fj);
            const double c00 = pix(i, j), c10 = pix(i + 1, j), c01 = pix(i, j + 1), c11 = pix(i + 1, j + 1);
            const bool all_in = c00 >= 0.5 && c10 >= 0.5 && c01 >= 0.5 && c11 >= 0.5;
            const bool all_out = c00 < 0.5 && c10 < 0.5 && c01 < 0.5 && c11 < 0.5;
            if (all_in || all_out) {
                if (cur != all_in) push(s_prev), cur = all_in;
            } else {
                // g(s) = bilinear(u(s) - i, v(s) - j) - 0.5 = q0 + q1 s + q2 s^2
                const double pu = u0 - fi, pv = v0 - fj;
                const double a1 = c10 - c00, a2 = c01 - c00, k = c00 - c10 - c01 + c11;
                const double q0 = c00 + a1 * pu + a2 * pv + k * pu * pv - 0.5;
                const double q1 = a1 * du + a2 * dv + k * (pu * dv + pv * du);
                const double q2 = k * du * dv;
                auto g = [&](double s) { return q0 + s * (q1 + s * q2); };
                double cuts[3] = {s_prev, s_next, s_next};
                int nc = 2;
                if (q2 != 0) {
                    const double se = -q1 / (2 * q2);
                    if (se > s_prev && se < s_next) cuts[1] = se, cuts[2] = s_next, nc = 3;
                }
                for (int c = 0; c + 1 < nc; ++c) {
                    const double lo = cuts[c], hi = cuts[c + 1];
                    const bool st_lo = g(lo) >= 0, st_hi = g(hi) >= 0;
                    if (st_lo != cur) push(lo), cur = st_lo;
                    if (st_hi != cur) push(monotone_root(q0, q1, q2, lo, hi)), cur = st_hi;
                }
            }
        }
        if (s_next >= 1.0) break;
        s_prev = s_next;
        if (take_u) ku += su;
        if (take_v) kv += sv;
        if (!take_u && !take_v) break;
    }
    return n;
}

int SilhouetteField::transitions(const Vec3d& a, const Vec3d& b, bool& start, double* flips, int max_flips) const {
    start = inside(a);
    const auto ha = project_h(a), hb = project_h(b);
    const double wa = ha[2], wb = hb[2];
    if (wa <= kMinDepth && wb <= kMinDepth) return 0;
    // The part of the segment in front of the camera: [t0, t1].
    double t0 = 0, t1 = 1;
    const double guard = 2 * kMinDepth;
    if (wa <= kMinDepth) t0 = (guard - wa) / (wb - wa);
    if (wb <= kMinDepth) t1 = (guard - wa) / (wb - wa);
    if (!(t1 > t0)) return 0;
    auto at = [&](double t, int c) { return ha[c] + t * (hb[c] - ha[c]); };
    const double w0 = at(t0, 2), w1 = at(t1, 2);
    const double x0 = at(t0, 0) / w0, y0 = at(t0, 1) / w0, x1 = at(t1, 0) / w1, y1 = at(t1, 1) / w1;
    int n = 0;
    bool cur = start;
    if (t0 > 0) {
        // Behind the camera up to t0: outside there.
        const bool in0 = coverage(x0, y0) >= 0.5;
        if (in0 && n < max_flips) flips[n++] = t0;
        cur = in0;
    }
    double local[256];
    const int cap = std::min(max_flips - n, 256);
    const int m = cap > 0 ? transitions_2d(x0, y0, x1, y1, cur, local, cap) : 0;
    const bool projective = !(view_->camera.orthographic());
    for (int k = 0; k < m; ++k) {
        const double s = local[k];
        // Image parameter s -> segment parameter: tau = s w0 / (s w0 + (1 - s) w1).
        const double tau = projective ? s * w0 / (s * w0 + (1 - s) * w1) : s;
        flips[n++] = t0 + (t1 - t0) * tau;
        cur = !cur;
    }
    if (t1 < 1 && cur && n < max_flips) flips[n++] = t1;
    return n;
}

double SilhouetteField::pixel_size_at(const Vec3d& p) const {
    const auto h = project_h(p);
    const double w = h[2];
    if (view_->camera.orthographic() || w <= kMinDepth) return 1.0 / std::max(view_->camera.scale, 1e-300);
    const double x = h[0] / w, y = h[1] / w;
    // Jacobian of the projection (2x3); the product of its singular values is sqrt(det(J J^T)).
    double J[2][3];
    for (int c = 0; c < 3; ++c) {
        J[0][c] = (m_[c] - x * m_[8 + c]) / w;
        J[1][c] = (m_[4 + c] - y * m_[8 + c]) / w;
    }
    double a = 0, b = 0, d = 0;
    for (int c = 0; c < 3; ++c) a += J[0][c] * J[0][c], b += J[0][c] * J[1][c], d += J[1][c] * J[1][c];
    const double det = a * d - b * b;
    return det > 0 ? 1.0 / std::sqrt(std::sqrt(det)) : 1.0;
}

} // namespace cm
