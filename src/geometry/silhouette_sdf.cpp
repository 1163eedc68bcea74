// The signed distance field of a silhouette (hull_distance.h: SilhouetteSdf) and the fields
// of a set of views.
#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/collaborative_call_once.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "geometry/distance_transform.h"
#include "geometry/hull_distance.h"

namespace cm {

namespace {
constexpr float kNotWorkedOut = std::numeric_limits<float>::infinity(); // squared_edt_signed()
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
} // namespace

// The field at a silhouette's window pixels not worked out and beyond the window: every such
// pixel is outside, farther than kSdfReach from the silhouette, so its value is its distance
// to the nearest inside pixel less half a pixel (no coverage refinement that far). Each part
// is built on first use from the window's inside pixels (all the inside pixels there are),
// once: threads that ask meanwhile help build it. The window's part is squared_edt() of its
// inside pixels, as the whole window's field was built before the window held the near
// pixels only.
class SdfBeyondWindow {
public:
    SdfBeyondWindow(UninitVector<char> inside, int ox, int oy, int stride, int rows, int w, int h)
        : inside_(std::move(inside)), ox_(ox), oy_(oy), stride_(stride), rows_(rows), w_(w), h_(h) {}
    float at(int i, int j) const {
        const int x = i - ox_, y = j - oy_;
        if (x >= 0 && y >= 0 && x < stride_ && y < rows_) {
            tbb::collaborative_call_once(window_once_,
                                         [&] { window_to_in_ = squared_edt(inside_.data(), stride_, rows_); });
            return std::sqrt(window_to_in_[std::size_t(y) * stride_ + x]) - 0.5f;
        }
        tbb::collaborative_call_once(image_once_, [&] {
            std::vector<char> seed(std::size_t(w_) * h_, 0);
            for (int r = 0; r < rows_; ++r)
                std::copy_n(inside_.data() + std::size_t(r) * stride_, stride_,
                            seed.data() + std::size_t(r + oy_) * w_ + ox_);
            image_to_in_ = squared_edt(seed, w_, h_);
        });
        return std::sqrt(image_to_in_[std::size_t(j) * w_ + i]) - 0.5f;
    }

private:
    UninitVector<char> inside_; // the window's inside pixels
    int ox_, oy_, stride_, rows_, w_, h_;
    mutable tbb::collaborative_once_flag window_once_, image_once_;
    mutable std::vector<float> window_to_in_, image_to_in_;
};

SilhouetteSdf silhouette_sdf(const std::vector<float>& coverage, int w, int h, const std::string& view_name) {
    if (w <= 0 || h <= 0 || coverage.size() != std::size_t(w) * h)
        throw Error("view \"" + view_name + "\": the silhouette does not match the image size");
    return silhouette_sdf(Coverage(coverage, w, h), view_name);
}

SilhouetteSdf silhouette_sdf(const Coverage& coverage, const std::string& view_name) {
    const int w = coverage.width(), h = coverage.height();
    if (w <= 0 || h <= 0) throw Error("view \"" + view_name + "\" has no silhouette");
    const Coverage::Box box = coverage.inside_box();
    if (box.empty()) throw Error("view \"" + view_name + "\" has an empty silhouette");
    SilhouetteSdf s;
    s.width = w;
    s.height = h;
    constexpr int m = SilhouetteSdf::kSdfMargin;
    s.ox = std::max(0, box.x0 - m);
    s.oy = std::max(0, box.y0 - m);
    s.stride = std::min(w, box.x1 + m + 1) - s.ox;
    s.rows = std::min(h, box.y1 + m + 1) - s.oy;
    const int sw = s.stride, sh = s.rows;
    const std::size_t n = std::size_t(sw) * sh;
    // The window's pixels that the coverage holds (it is 0 beyond them): [cx0, cx1) of a row.
    const int cx0 = std::clamp(coverage.x0() - s.ox, 0, sw);
    const int cx1 = std::clamp(coverage.x0() + coverage.window_width() - s.ox, cx0, sw);
    auto coverage_row = [&](int y) {
        const float* c = coverage.window_row(y + s.oy);
        return c ? c + (s.ox + cx0 - coverage.x0()) : nullptr; // at column cx0
    };
    // The arrays are left unset by their constructors and written first side by side.
    UninitVector<char> inside(n);
    tbb::parallel_for(tbb::blocked_range<int>(0, sh, 16), [&](const tbb::blocked_range<int>& r) {
        for (int y = r.begin(); y != r.end(); ++y) {
            char* in = inside.data() + std::size_t(y) * sw;
            const float* c = coverage_row(y);
            std::fill(in, in + sw, char(0));
            if (c)
                for (int x = cx0; x < cx1; ++x) in[x] = c[x - cx0] >= 0.5f;
        }
    });
    s.sdf.resize(n);
    squared_edt_signed(inside.data(), sw, sh, SilhouetteSdf::kSdfReach, [&](int y, const float* d2) {
        const auto* in = reinterpret_cast<const unsigned char*>(inside.data()) + std::size_t(y) * sw;
        float* out = s.sdf.data() + std::size_t(y) * sw;
        // The binary border lies half-way between an inside and an outside pixel centre; a
        // pixel of fractional coverage within half a pixel of it is refined to 0.5 - coverage.
        // The pixels not worked out (infinity) get NaN. Selects only: the loops are
        // vectorised (this file is built without errno for std::sqrt).
        auto value = [&](int x) {
            const float d = std::sqrt(d2[x]) - 0.5f;
            return d2[x] == kNotWorkedOut ? kNaN : (in[x] ? -d : d);
        };
        for (int x = 0; x < cx0; ++x) out[x] = value(x);
        if (const float* c = coverage_row(y)) {
            for (int x = cx0; x < cx1; ++x) {
                const float v = value(x), cv = c[x - cx0];
                out[x] = cv > 0.0f && cv < 1.0f && std::fabs(v) <= 0.5f ? 0.5f - cv : v;
            }
        } else {
            for (int x = cx0; x < cx1; ++x) out[x] = value(x);
        }
        for (int x = cx1; x < sw; ++x) out[x] = value(x);
    });
    // The field beyond: for the pixels beyond the window, and those not worked out (which a
    // window that is the whole image may also have).
    if (sw != w || sh != h || std::any_of(s.sdf.begin(), s.sdf.end(), [](float v) { return std::isnan(v); }))
        s.beyond = std::make_shared<const SdfBeyondWindow>(std::move(inside), s.ox, s.oy, sw, sh, w, h);
    return s;
}

float SilhouetteSdf::at(int i, int j) const {
    const int x = i - ox, y = j - oy;
    if (x >= 0 && y >= 0 && x < stride && y < rows) {
        const float v = sdf[std::size_t(y) * stride + x];
        if (!std::isnan(v)) return v;
    }
    return beyond->at(i, j);
}

double SilhouetteSdf::sample_edge(double x, double y) const {
    // A point that projects nowhere (a coordinate overflowed) is outside every silhouette.
    if (!std::isfinite(x) || !std::isfinite(y)) return std::numeric_limits<double>::infinity();
    // Pixel-centre lattice coordinates.
    double fx = x - 0.5, fy = y - 0.5;
    const double cx = std::clamp(fx, 0.0, double(width - 1));
    const double cy = std::clamp(fy, 0.0, double(height - 1));
    const bool in_frame = fx == cx && fy == cy;
    const int x0 = std::min(int(cx), width - 1), y0 = std::min(int(cy), height - 1);
    const int x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
    const double tx = cx - x0, ty = cy - y0;
    auto v_at = [&](int i, int j) { return double(at(i, j)); };
    const double v =
        (1 - ty) * ((1 - tx) * v_at(x0, y0) + tx * v_at(x1, y0)) + ty * ((1 - tx) * v_at(x0, y1) + tx * v_at(x1, y1));
    if (in_frame) return v;
    // Beyond the image: at least as far as the border sample plus the way out.
    const double beyond_image = std::hypot(fx - cx, fy - cy);
    return beyond_image > 0 ? std::max(v, 0.0) + beyond_image : v;
}

std::vector<ViewSdf> view_sdfs(const Views& views) {
    // The views' fields are independent: built side by side. The first failing view in
    // order is reported, whichever thread found it first.
    std::vector<ViewSdf> out(views.views.size());
    std::vector<std::string> errors(views.views.size());
    tbb::parallel_for(std::size_t(0), views.views.size(), [&](std::size_t i) {
        const View& v = views.views[i];
        try {
            out[i] = {v.camera, silhouette_sdf(v.coverage, v.name)};
        } catch (const std::exception& e) {
            errors[i] = e.what();
        }
    });
    for (const auto& e : errors)
        if (!e.empty()) throw Error(e);
    return out;
}

} // namespace cm
