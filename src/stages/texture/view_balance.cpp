#include "view_balance.h"

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "render/colour.h"

namespace cm {
namespace {

// Pixels this close to the silhouette's border are not judged (as `compare` leaves them
// out): the drawing's outline and a hull's rim meet there to within a pixel or two.
constexpr float kJudgedInside = 3.0f;

// A pixel of a view: the surface point it shows, what every view that sees the point says
// of it, and which of those samples is its own view's.
struct PixelPoint {
    int view = 0, x = 0, y = 0;
    int first = 0, count = 0, own = -1;
};

double lab_distance(const std::array<double, 3>& a, const std::array<double, 3>& b) {
    return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

// Mean delta E per view with the views' `weight`.
std::vector<double> view_errors(const std::vector<PixelPoint>& pts, std::vector<ViewSample>& vs,
                                const std::vector<double>& weight, const SurfaceColourOptions& opt) {
    for (ViewSample& s : vs) s.weight = weight[std::size_t(s.view)];
    std::vector<double> de(pts.size(), 0.0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pts.size()), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) {
            if (pts[i].count == 1) continue; // seen by its own view alone: its own colour
            const ViewSample* s = &vs[std::size_t(pts[i].first)];
            de[i] = lab_distance(srgb_to_lab(combine_samples(s, pts[i].count, opt)), s[pts[i].own].lab);
        }
    });
    // Summed in order, one thread: the same figures whatever the threads.
    std::vector<double> sum(weight.size(), 0.0), n(weight.size(), 0.0);
    for (std::size_t i = 0; i < pts.size(); ++i) {
        sum[std::size_t(pts[i].view)] += de[i];
        n[std::size_t(pts[i].view)] += 1;
    }
    for (std::size_t v = 0; v < sum.size(); ++v) sum[v] = n[v] > 0 ? sum[v] / n[v] : 0.0;
    return sum;
}

// The steps of balance_views over the pixels they judge: the pixels and what the views say
// of the points they show (made once), then the weights searched against the errors.
class Balancer {
public:
    Balancer(const std::vector<ViewSampler>& views, const SurfaceColourOptions& opt, double target)
        : views_(views), opt_(opt), target_(target), nv_(views.size()) {}

    /// Step 1: every view's covered pixels where its drawing has a colour, on a grid with a
    /// stride that keeps them to about `samples`.
    void pick_pixels(std::size_t samples) {
        std::size_t covered = 0;
        for (const ViewSampler& v : views_)
            for (std::uint32_t f : v.depth.face) covered += f != DepthImage::kNoFace ? 1 : 0;
        const int stride =
            std::max(1, int(std::ceil(std::sqrt(double(covered) / double(std::max<std::size_t>(samples, 1))))));
        for (std::size_t v = 0; v < nv_; ++v) {
            const DepthImage& d = views_[v].depth;
            for (int y = stride / 2; y < d.height; y += stride)
                for (int x = stride / 2; x < d.width; x += stride)
                    if (d.covered(x, y) && views_[v].colours.drawn[std::size_t(y) * d.width + x] &&
                        views_[v].colours.border_px[std::size_t(y) * d.width + x] > kJudgedInside)
                        pts_.push_back({int(v), x, y, 0, 0, -1});
        }
    }

    /// Step 2: what every view that sees a pixel's surface point says of it. A pixel whose
    /// own view does not pass its point (a grazing surface) is left out.
    void ask_views(const Mesh& mesh) {
        const int per_point = int(std::min<std::size_t>(nv_, kMaxViewSamples));
        vs_.resize(pts_.size() * std::size_t(per_point));
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pts_.size()),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              ViewSample tmp[kMaxViewSamples];
                              for (std::size_t i = r.begin(); i < r.end(); ++i) ask(mesh, i, per_point, tmp);
                          });
        pts_.erase(std::remove_if(pts_.begin(), pts_.end(), [](const PixelPoint& p) { return p.own < 0; }), pts_.end());
    }

    /// Mean delta E per view with the views' `weight`.
    std::vector<double> errors(const std::vector<double>& weight) { return view_errors(pts_, vs_, weight, opt_); }

    /// Step 3: every view's pixels counting alike: a view's weight is its pixel density (pixels
    /// per unit area facing it) over its pixel count, so what a point's colour makes small is
    /// the sum of the views' mean errors. False when no view has a pixel.
    bool count_pixels() {
        npix_.assign(nv_, 0.0);
        for (const PixelPoint& p : pts_) npix_[std::size_t(p.view)] += 1;
        base_.assign(nv_, 0.0);
        int seen = 0;
        for (std::size_t v = 0; v < nv_; ++v)
            if (npix_[v] > 0) {
                base_[v] = 1.0 / (views_[v].pixel_world * views_[v].pixel_world * npix_[v]);
                mean_base_ += base_[v];
                ++seen;
            }
        if (seen == 0) return false;
        mean_base_ /= seen;
        return true;
    }

    /// The weights of the views' factors on their pixel-count weights.
    std::vector<double> weights_of(const std::vector<double>& f) const {
        std::vector<double> w(nv_, 1.0);
        for (std::size_t v = 0; v < nv_; ++v)
            if (npix_[v] > 0) w[v] = f[v] * base_[v] / mean_base_;
        return w;
    }

    /// Step 4: each view's factor on its pixel-count weight, found by a pattern search in
    /// powers of two (the errors change in steps as regions of the surface go from one view's
    /// colour to another's, so there is no slope to follow): the views in order of their
    /// error, the worst first, each tried with more weight (or less, for a view under the
    /// target) and then the other way; the first change that scores better is kept and the
    /// search starts again from the worst view; when none does, the step halves. `out` holds
    /// the weights and errors of the factors 1, and then of the best found.
    void search(ViewBalance& out, int rounds) {
        std::vector<double> factor(nv_, 1.0);
        // With every view under the target already, the weights stay as they are: the search
        // would only trade one view's error for another's by what the estimate says.
        int evaluations = *std::max_element(out.error.begin(), out.error.end()) > target_ ? 1 : rounds;
        double step = 2.0; // log2 of the change
        while (evaluations < rounds && step >= 0.125) {
            std::vector<std::size_t> order;
            for (std::size_t v = 0; v < nv_; ++v)
                if (npix_[v] > 0) order.push_back(v);
            std::stable_sort(order.begin(), order.end(),
                             [&](std::size_t x, std::size_t y) { return out.error[x] > out.error[y]; });
            bool improved = false;
            for (std::size_t v : order) {
                const double first = out.error[v] > target_ ? 1.0 : -1.0;
                for (double dir : {first, -first}) {
                    if (evaluations >= rounds) break;
                    std::vector<double> f = factor;
                    f[v] *= std::exp2(dir * step);
                    double least = 1e300;
                    for (std::size_t k : order) least = std::min(least, f[k]);
                    for (std::size_t k : order) f[k] /= least;
                    const std::vector<double> w = weights_of(f);
                    const std::vector<double> err = errors(w);
                    ++evaluations;
                    if (better(err, out.error)) {
                        factor = f;
                        out.weight = w;
                        out.error = err;
                        improved = true;
                        break;
                    }
                }
                if (improved) break;
            }
            if (!improved) step *= 0.5;
        }
    }

private:
    // The samples of pixel i: the point of its face the pixel centre's ray meets, with its
    // interpolated normal, as the views see it.
    void ask(const Mesh& mesh, std::size_t i, int per_point, ViewSample* tmp) {
        PixelPoint& pp = pts_[i];
        const Camera& cam = views_[std::size_t(pp.view)].view->camera;
        const DepthImage& d = views_[std::size_t(pp.view)].depth;
        const auto& t = mesh.triangles[d.face[std::size_t(pp.y) * d.width + pp.x]];
        const Vec3d a(mesh.positions[t[0]]), b(mesh.positions[t[1]]), c(mesh.positions[t[2]]);
        const Vec3d fn = cross(b - a, c - a);
        Vec3d o, dir;
        cam.ray(pp.x + 0.5, pp.y + 0.5, o, dir);
        const double den = dot(dir, fn), nn = dot(fn, fn);
        if (std::abs(den) < 1e-300 || !(nn > 0)) return;
        const Vec3d p = o + dir * (dot(a - o, fn) / den);
        const double wa = std::clamp(dot(cross(b - p, c - p), fn) / nn, 0.0, 1.0);
        const double wb = std::clamp(dot(cross(c - p, a - p), fn) / nn, 0.0, 1.0);
        const double wc = std::max(0.0, 1.0 - wa - wb);
        const Vec3d n =
            normalize(Vec3d(mesh.normals[t[0]]) * wa + Vec3d(mesh.normals[t[1]]) * wb + Vec3d(mesh.normals[t[2]]) * wc);
        const int count = std::min(view_samples(views_, p, n, opt_, tmp, true), per_point);
        pp.first = int(i) * per_point;
        for (int k = 0; k < count; ++k) {
            vs_[std::size_t(pp.first + k)] = tmp[k];
            if (tmp[k].view == pp.view) pp.own = k;
        }
        pp.count = count;
    }

    // The score of a set of errors: the worst view's error above the target, then the sum.
    bool better(const std::vector<double>& a, const std::vector<double>& b) const {
        double wa = target_, wb = target_, sa = 0, sb = 0;
        for (std::size_t v = 0; v < nv_; ++v) {
            wa = std::max(wa, a[v]);
            wb = std::max(wb, b[v]);
            sa += a[v];
            sb += b[v];
        }
        if (std::abs(wa - wb) > 1e-3 * std::max(1.0, wb)) return wa < wb;
        return sa < sb - 1e-9;
    }

    const std::vector<ViewSampler>& views_;
    const SurfaceColourOptions& opt_;
    const double target_;
    const std::size_t nv_;
    std::vector<PixelPoint> pts_;
    std::vector<ViewSample> vs_; ///< per pixel point, up to kMaxViewSamples from its `first`
    std::vector<double> npix_;   ///< per view: its pixels
    std::vector<double> base_;   ///< per view: its weight with every view's pixels counting alike
    double mean_base_ = 0;       ///< of the views with pixels
};

} // namespace

ViewBalance balance_views(const Mesh& mesh, const std::vector<ViewSampler>& views, const SurfaceColourOptions& opt,
                          int rounds, double target, std::size_t samples) {
    const std::size_t nv = views.size();
    ViewBalance out;
    out.weight.assign(nv, 1.0);
    out.error_before.assign(nv, 0.0);
    out.error.assign(nv, 0.0);
    if (nv == 0 || mesh.triangles.empty()) return out;
    Balancer b(views, opt, target);
    b.pick_pixels(samples);
    b.ask_views(mesh);
    out.error_before = b.errors(out.weight);
    out.error = out.error_before;
    if (rounds <= 0 || !b.count_pixels()) return out;
    out.weight = b.weights_of(std::vector<double>(nv, 1.0));
    out.error = b.errors(out.weight);
    b.search(out, rounds);
    double mean_weight = 0;
    for (double w : out.weight) mean_weight += w / double(nv);
    for (double& w : out.weight) w /= mean_weight;
    return out;
}

} // namespace cm
