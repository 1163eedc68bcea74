#include "metrics/silhouette_error.h"

#include <cstdio>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include "core/error.h"

namespace cm {

SilhouetteError silhouette_error(const Mesh& mesh, const Views& views, std::vector<std::vector<std::uint8_t>>* masks,
                                 const RenderCheck& check) {
    SilhouetteError res;
    if (masks) masks->clear();
    double sum_xor = 0, sum_input = 0, sum_iou = 0;
    for (const View& v : views.views) {
        if (v.coverage.size() != std::size_t(v.width) * v.height || v.width <= 0 || v.height <= 0)
            throw Error("view \"" + v.name + "\" has no silhouette to compare with");
        std::vector<std::uint8_t> r = render_mask(mesh, v.camera, v.width, v.height, check);
        struct Counts {
            std::size_t s = 0, r = 0, both = 0;
        };
        // By rows: the mask's pixels over the whole row, the silhouette's over its window (zero
        // beyond it). 32-bit counts per row: a loop over several pixels at once.
        const Coverage& cov = v.coverage;
        const int x0 = cov.x0(), ww = cov.window_width();
        const Counts c = tbb::parallel_reduce(
            tbb::blocked_range<int>(0, v.height, 32), Counts{},
            [&](const tbb::blocked_range<int>& rows, Counts acc) {
                for (int y = rows.begin(); y != rows.end(); ++y) {
                    const std::uint8_t* mask = r.data() + std::size_t(y) * std::size_t(v.width);
                    std::uint32_t s = 0, m = 0, both = 0;
                    for (int x = 0; x < v.width; ++x) m += mask[x] != 0 ? 1u : 0u;
                    if (const float* row = cov.window_row(y))
                        for (int x = 0; x < ww; ++x) {
                            const std::uint32_t si = row[x] >= 0.5f ? 1u : 0u, mi = mask[x0 + x] != 0 ? 1u : 0u;
                            s += si;
                            both += si & mi;
                        }
                    acc.s += s;
                    acc.r += m;
                    acc.both += both;
                }
                return acc;
            },
            [](Counts x, const Counts& y) {
                x.s += y.s;
                x.r += y.r;
                x.both += y.both;
                return x;
            });
        ViewError e;
        e.view = v.name;
        e.input_px = double(c.s);
        e.render_px = double(c.r);
        e.xor_px = double(c.s + c.r - 2 * c.both);
        const double uni = double(c.s + c.r - c.both);
        e.iou = uni > 0 ? double(c.both) / uni : 1.0;
        e.xor_pct = c.s > 0 ? 100.0 * e.xor_px / e.input_px : (c.r > 0 ? 100.0 : 0.0);
        sum_xor += e.xor_px;
        sum_input += e.input_px;
        sum_iou += e.iou;
        res.views.push_back(e);
        if (masks) masks->push_back(std::move(r));
    }
    res.xor_pct = sum_input > 0 ? 100.0 * sum_xor / sum_input : (sum_xor > 0 ? 100.0 : 0.0);
    res.mean_iou = res.views.empty() ? 0.0 : sum_iou / double(res.views.size());
    return res;
}

std::shared_ptr<const SilhouetteRenders> shared_silhouette_error(const std::shared_ptr<const Mesh>& mesh,
                                                                 const Views& views, const RenderCheck& check) {
    auto make = [&] {
        auto r = std::make_shared<SilhouetteRenders>();
        r->error = silhouette_error(*mesh, views, &r->masks, check);
        r->mesh = mesh;
        return r;
    };
    char key[64];
    std::snprintf(key, sizeof key, "silhouette_error@%p", static_cast<const void*>(mesh.get()));
    auto kept = std::static_pointer_cast<const SilhouetteRenders>(
        views.derived.get(key, [&]() -> std::shared_ptr<const void> { return make(); }));
    // Kept for a mesh since let go, whose memory this one now has: made afresh, not kept.
    if (kept->mesh.lock() != mesh) return make();
    return kept;
}

} // namespace cm
