#include "core/views.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace cm {

// The image and window of a Coverage to be made from `part`, with the box of its nonzero
// values (`nonzero`, in the part's coordinates; empty when all are zero) and that of its
// inside ones (set on the Coverage).
Coverage Coverage::frame(const std::vector<float>& part, int width, int height, int x0, int y0, int w, int h,
                         Box& nonzero) {
    if (width < 0 || height < 0 || w < 0 || h < 0 || part.size() != std::size_t(w) * std::size_t(h) || x0 < 0 ||
        y0 < 0 || x0 + w > width || y0 + h > height)
        throw std::invalid_argument("Coverage: the window does not fit the image");
    Coverage c;
    c.width_ = width;
    c.height_ = height;
    // The box of the nonzero values within the window, and that of the inside ones (>= 0.5).
    int bx0 = w, by0 = h, bx1 = -1, by1 = -1;
    for (int y = 0; y < h; ++y) {
        const float* row = part.data() + std::size_t(y) * std::size_t(w);
        int first = 0;
        while (first < w && row[first] == 0.0f) ++first;
        if (first == w) continue;
        int last = w - 1;
        while (row[last] == 0.0f) --last;
        bx0 = std::min(bx0, first);
        bx1 = std::max(bx1, last);
        by0 = std::min(by0, y);
        by1 = y;
        int in_first = first;
        while (in_first <= last && !(row[in_first] >= 0.5f)) ++in_first;
        if (in_first > last) continue;
        int in_last = last;
        while (!(row[in_last] >= 0.5f)) --in_last;
        Box& b = c.inside_;
        if (b.empty()) b = {x0 + in_first, y0 + y, x0 + in_last, y0 + y};
        b = {std::min(b.x0, x0 + in_first), b.y0, std::max(b.x1, x0 + in_last), y0 + y};
    }
    nonzero = {bx0, by0, bx1, by1};
    if (bx1 < 0) return c; // all zero: an empty window
    c.x0_ = x0 + bx0;
    c.y0_ = y0 + by0;
    c.w_ = bx1 - bx0 + 1;
    c.h_ = by1 - by0 + 1;
    return c;
}

Coverage Coverage::of_window(const std::vector<float>& part, int width, int height, int x0, int y0, int w, int h) {
    Box box;
    Coverage c = frame(part, width, height, x0, y0, w, h, box);
    if (box.empty()) return c;
    c.values_.resize(std::size_t(c.w_) * std::size_t(c.h_));
    for (int y = 0; y < c.h_; ++y)
        std::copy_n(part.data() + std::size_t(box.y0 + y) * std::size_t(w) + std::size_t(box.x0), c.w_,
                    c.values_.data() + std::size_t(y) * std::size_t(c.w_));
    return c;
}

Coverage Coverage::of_window(std::vector<float>&& part, int width, int height, int x0, int y0, int w, int h) {
    Box box;
    Coverage c = frame(part, width, height, x0, y0, w, h, box);
    if (box.empty()) return c;
    // The box's rows moved to the front in order: each lands at or before where it was read
    // (memmove: a row may overlap where it goes).
    for (int y = 0; y < c.h_; ++y)
        std::memmove(part.data() + std::size_t(y) * std::size_t(c.w_),
                     part.data() + std::size_t(box.y0 + y) * std::size_t(w) + std::size_t(box.x0),
                     std::size_t(c.w_) * sizeof(float));
    part.resize(std::size_t(c.w_) * std::size_t(c.h_));
    c.values_ = std::move(part);
    return c;
}

Coverage::Coverage(const std::vector<float>& full, int width, int height)
    : Coverage(of_window(full, width, height, 0, 0, width, height)) {}

std::vector<float> Coverage::full() const {
    std::vector<float> out(size(), 0.0f);
    for (int y = 0; y < h_; ++y)
        std::copy_n(values_.data() + std::size_t(y) * std::size_t(w_), w_,
                    out.data() + std::size_t(y0_ + y) * std::size_t(width_) + std::size_t(x0_));
    return out;
}

double Views::finest_pixel() const {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& v : views)
        if (v.camera.orthographic() && v.camera.scale > 0) best = std::min(best, 1.0 / v.camera.scale);
    return std::isfinite(best) ? best : units_per_pixel;
}

} // namespace cm
