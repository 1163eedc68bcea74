#include "metrics/silhouette_error.h"

#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "render/raster.h"

namespace cm {

namespace {

nlohmann::json views_array(const SilhouetteError& e) {
    nlohmann::json a = nlohmann::json::array();
    for (const auto& v : e.views)
        a.push_back({{"view", v.view},
                     {"xor_pct", v.xor_pct},
                     {"iou", v.iou},
                     {"input_px", v.input_px},
                     {"render_px", v.render_px},
                     {"xor_px", v.xor_px}});
    return a;
}

} // namespace

SilhouetteMask silhouette_mask(const Mesh& mesh, const View& v, Progress progress) {
    if (v.coverage.size() != std::size_t(v.width) * v.height || v.width <= 0 || v.height <= 0)
        throw Error("view \"" + v.name + "\" has no silhouette to compare with");
    return render_mask(mesh, v.camera, v.width, v.height, std::move(progress));
}

ViewError view_error(const View& v, const SilhouetteMask& mask) {
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
                const std::uint8_t* row_mask = mask.data() + std::size_t(y) * std::size_t(v.width);
                std::uint32_t s = 0, m = 0, both = 0;
                for (int x = 0; x < v.width; ++x) m += row_mask[x] != 0 ? 1u : 0u;
                if (const float* row = cov.window_row(y))
                    for (int x = 0; x < ww; ++x) {
                        const std::uint32_t si = row[x] >= 0.5f ? 1u : 0u, mi = row_mask[x0 + x] != 0 ? 1u : 0u;
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
    return e;
}

SilhouetteError combine_view_errors(std::vector<ViewError> views) {
    SilhouetteError res;
    res.views = std::move(views);
    double sum_xor = 0, sum_input = 0, sum_iou = 0;
    for (const ViewError& e : res.views) {
        sum_xor += e.xor_px;
        sum_input += e.input_px;
        sum_iou += e.iou;
    }
    res.xor_pct = sum_input > 0 ? 100.0 * sum_xor / sum_input : (sum_xor > 0 ? 100.0 : 0.0);
    res.mean_iou = res.views.empty() ? 0.0 : sum_iou / double(res.views.size());
    return res;
}

SilhouetteError silhouette_error(const Mesh& mesh, const Views& views, Progress progress) {
    std::vector<ViewError> errors;
    for (const View& v : views.views) errors.push_back(view_error(v, silhouette_mask(mesh, v, progress)));
    return combine_view_errors(std::move(errors));
}

void SilhouetteError::report(Metrics& m) const {
    for (const auto& v : views) {
        m.metric("xor_pct." + v.view, v.xor_pct);
        m.metric("iou." + v.view, v.iou);
    }
    m.metric("xor_pct", xor_pct);
    m.metric("mean_iou", mean_iou);
    m.metric_json("views", views_json());
}

std::string SilhouetteError::views_json() const { return views_array(*this).dump(); }

std::string SilhouetteError::json() const {
    nlohmann::json j;
    j["xor_pct"] = xor_pct;
    j["mean_iou"] = mean_iou;
    j["views"] = views_array(*this);
    return j.dump();
}

} // namespace cm
