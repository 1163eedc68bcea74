#include "opposite_holes.h"

#include <algorithm>
#include <cmath>

namespace cm {

namespace {

// A candidate's centre in [0, 1] across its silhouette's box, and its area over the box's.
struct Placed {
    double u = 0, v = 0, area = 0;
};

Placed place(const View& v, const EnclosedRegion& g) {
    const Coverage::Box& b = v.coverage.inside_box();
    const double w = std::max(1, b.x1 - b.x0 + 1), h = std::max(1, b.y1 - b.y0 + 1);
    return {(g.x - b.x0 + 0.5) / w, (g.y - b.y0 + 0.5) / h, double(g.area) / (w * h)};
}

// The view's coverage with the region's pixels made background.
void open_region(View& v, const EnclosedRegion& g) {
    const Coverage& c = v.coverage;
    std::vector<float> values = c.window_values();
    const int W = c.width(), x0 = c.x0(), y0 = c.y0(), w = c.window_width(), h = c.window_height();
    for (const std::uint32_t p : g.pixels) {
        const int x = int(p % std::uint32_t(W)) - x0, y = int(p / std::uint32_t(W)) - y0;
        if (x >= 0 && y >= 0 && x < w && y < h) values[std::size_t(y) * w + x] = 0.0f;
    }
    v.coverage = Coverage::of_window(std::move(values), W, c.height(), x0, y0, w, h);
}

} // namespace

std::vector<std::string> open_confirmed_holes(std::vector<View>& views,
                                              std::vector<std::vector<EnclosedRegion>>& regions) {
    std::vector<std::string> notes;
    for (std::size_t a = 0; a < views.size(); ++a)
        for (std::size_t b = a + 1; b < views.size(); ++b) {
            const Camera &ca = views[a].camera, &cb = views[b].camera;
            if (dot(ca.d, cb.d) > -0.99) continue; // not opposite
            const double rr = dot(ca.r, cb.r), uu = dot(ca.u, cb.u);
            if (std::abs(rr) < 0.99 || std::abs(uu) < 0.99) continue; // image axes turned
            for (EnclosedRegion& ga : regions[a]) {
                if (!(ga.candidate || ga.witness) || ga.hole) continue;
                Placed pa = place(views[a], ga);
                if (rr < 0) pa.u = 1 - pa.u;
                if (uu < 0) pa.v = 1 - pa.v;
                for (EnclosedRegion& gb : regions[b]) {
                    // A witness confirms a candidate; two witnesses are the inside twice.
                    if (!(gb.candidate || gb.witness) || gb.hole || !(ga.candidate || gb.candidate)) continue;
                    const Placed pb = place(views[b], gb);
                    const double ratio = pa.area / std::max(1e-12, pb.area);
                    // A gap between parts is bounded by the silhouette's own outline, which
                    // both views draw alike: it must match closely (2 % of the box, areas
                    // within 15 %); so must a witness, the region's own outline seen from
                    // the other side. A nested loop is drawn by each view's own lines.
                    const bool outline = ga.between_parts || gb.between_parts || ga.witness || gb.witness;
                    const double near = outline ? 0.02 : 0.1, spread = outline ? 1.15 : 2.0;
                    if (std::hypot(pa.u - pb.u, pa.v - pb.v) > near || ratio > spread || ratio * spread < 1) continue;
                    ga.hole = gb.hole = true;
                    ga.why = gb.why = "line art, shown by the opposite view";
                    open_region(views[a], ga);
                    open_region(views[b], gb);
                    notes.push_back("views \"" + views[a].name + "\" and \"" + views[b].name +
                                    "\" both show an opening: opened, " + std::to_string(ga.area) + " px at (" +
                                    std::to_string(ga.x) + ", " + std::to_string(ga.y) + ") and " +
                                    std::to_string(gb.area) + " px at (" + std::to_string(gb.x) + ", " +
                                    std::to_string(gb.y) + ")");
                    break;
                }
            }
        }
    return notes;
}

} // namespace cm
