#include "align.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

#include "core/error.h"

namespace cm {

namespace {

// Sub-pixel extent of a silhouette along image x and y: the covered area per
// column/row, measured from the first to the last covered pixel.
struct Extent {
    double x0 = 0, x1 = 0, y0 = 0, y1 = 0;
};

Extent silhouette_extent(const View& v) {
    const int w = v.width, h = v.height;
    std::vector<double> col(w, 0.0), row(h, 0.0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double c = v.coverage_at(x, y);
            col[x] = std::max(col[x], c);
            row[y] = std::max(row[y], c);
        }
    auto range = [](const std::vector<double>& a, double& lo, double& hi) {
        int first = -1, last = -1;
        for (int i = 0; i < int(a.size()); ++i)
            if (a[i] >= 0.5) { if (first < 0) first = i; last = i; }
        if (first < 0) return false;
        // Partial coverage of the neighbouring pixel moves the edge by a fraction.
        lo = first + 0.5 - (first > 0 ? a[first - 1] : 0.0) - (a[first] - 0.5);
        hi = last + 0.5 + (last + 1 < int(a.size()) ? a[last + 1] : 0.0) + (a[last] - 0.5);
        return true;
    };
    Extent e;
    if (!range(col, e.x0, e.x1) || !range(row, e.y0, e.y1))
        throw Error("view \"" + v.name + "\" (" + v.source.string() + ") has an empty silhouette: no object was found in it");
    return e;
}

// Which world axis (0=X,1=Y,2=Z) a unit vector lies along, or -1.
int axis_of(const Vec3d& a) {
    for (int k = 0; k < 3; ++k)
        if (std::abs(std::abs(a[k]) - 1.0) < 1e-9) return k;
    return -1;
}

const char* axis_name(int k) { return k == 0 ? "width (X)" : k == 1 ? "height (Y)" : "depth (Z)"; }

} // namespace

void align_views(Views& views, const AlignOptions& opt, std::vector<std::string>& warnings) {
    const std::size_t n = views.views.size();
    std::vector<Extent> ext(n);
    for (std::size_t i = 0; i < n; ++i) ext[i] = silhouette_extent(views.views[i]);

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
                if (size[a] < 0) { size[a] = world; measured_by[a] = views.views[i].name; changed = true; }
                else if (std::abs(world - size[a]) > opt.tolerance * size[a]) {
                    std::ostringstream os;
                    os.precision(3);
                    os << "views \"" << measured_by[a] << "\" and \"" << views.views[i].name << "\" disagree on the "
                       << axis_name(a) << ": " << size[a] << " against " << world << " units ("
                       << 100.0 * std::abs(world - size[a]) / size[a] << "% apart)";
                    const std::string msg = os.str();
                    bool seen = false;
                    for (const auto& w : warnings) seen |= w == msg;
                    if (!seen) warnings.push_back(msg);
                }
            };
            record(ar, wr);
            record(au, hu);
        }
    }
    for (std::size_t i = 0; i < n; ++i)
        if (scale[i] < 0) scale[i] = 1.0;   // shares no axis (e.g. an oblique view): same scale as the first
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
        // Range of p.r and p.u over the box; its low edge in r maps to x0, its high edge in u to y0.
        double rmin = 0, umax = 0;
        for (int k = 0; k < 3; ++k) {
            rmin += std::min(c.r[k] * views.bounds_min[k], c.r[k] * views.bounds_max[k]);
            umax += std::max(c.u[k] * views.bounds_min[k], c.u[k] * views.bounds_max[k]);
        }
        if (axis_of(c.r) >= 0 && axis_of(c.u) >= 0) {
            c.cx = ext[i].x0 - c.scale * rmin;
            c.cy = ext[i].y0 + c.scale * umax;
        } else {
            // Oblique view: centre the box's projection on the silhouette's centre.
            const Vec3d mid = (views.bounds_min + views.bounds_max) * 0.5;
            c.cx = 0.5 * (ext[i].x0 + ext[i].x1) - c.scale * dot(mid, c.r);
            c.cy = 0.5 * (ext[i].y0 + ext[i].y1) + c.scale * dot(mid, c.u);
        }
    }
}

} // namespace cm
