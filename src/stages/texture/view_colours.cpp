#include "view_colours.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "geometry/distance_transform.h"

namespace cm {
namespace {

// Running max (or min) over a window of 2r+1 along rows, then along columns.
std::vector<float> box_filter(const std::vector<float>& in, int w, int h, int r, bool take_max) {
    std::vector<float> tmp(in.size()), out(in.size());
    auto pick = [take_max](float a, float b) { return take_max ? std::max(a, b) : std::min(a, b); };
    tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y < rows.end(); ++y)
            for (int x = 0; x < w; ++x) {
                float v = in[std::size_t(y) * w + x];
                for (int k = std::max(0, x - r); k <= std::min(w - 1, x + r); ++k)
                    v = pick(v, in[std::size_t(y) * w + k]);
                tmp[std::size_t(y) * w + x] = v;
            }
    });
    tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y < rows.end(); ++y)
            for (int x = 0; x < w; ++x) {
                float v = tmp[std::size_t(y) * w + x];
                for (int k = std::max(0, y - r); k <= std::min(h - 1, y + r); ++k)
                    v = pick(v, tmp[std::size_t(k) * w + x]);
                out[std::size_t(y) * w + x] = v;
            }
    });
    return out;
}

float luminance(const Image& img, int x, int y) {
    if (img.channels < 3) return img.at(x, y, 0);
    return 0.2126f * img.at(x, y, 0) + 0.7152f * img.at(x, y, 1) + 0.0722f * img.at(x, y, 2);
}

} // namespace

std::vector<char> find_ink(const Image& img, const std::vector<char>& inside, float line_width, float line_contrast) {
    const int w = img.width, h = img.height;
    std::vector<float> lum(std::size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) lum[std::size_t(y) * w + x] = luminance(img, x, y);
    const int r = std::max(1, int(std::ceil(line_width * 0.5f)));
    // Black top-hat: the closing (max then min) fills every dark feature narrower than the
    // window with the fill around it; what it raised by more than the contrast is ink.
    const std::vector<float> closed = box_filter(box_filter(lum, w, h, r, true), w, h, r, false);
    std::vector<char> ink(lum.size(), 0);
    for (std::size_t i = 0; i < lum.size(); ++i) ink[i] = inside[i] && closed[i] - lum[i] > line_contrast;
    std::vector<char> grown = ink;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            if (ink[i] || !inside[i]) continue;
            for (int dy = -1; dy <= 1 && !grown[i]; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if (xx >= 0 && yy >= 0 && xx < w && yy < h && ink[std::size_t(yy) * w + xx]) {
                        grown[i] = 1;
                        break;
                    }
                }
        }
    return grown;
}

ViewColours clean_view_colours(const View& view, const DepthImage* depth, double depth_jump, const CleanOptions& opt) {
    const Image& img = view.image;
    const int w = img.width, h = img.height;
    const std::size_t n = std::size_t(w) * h;
    ViewColours vc;
    vc.width = w;
    vc.height = h;
    vc.rgb.resize(n);
    vc.confidence.assign(n, 0.0f);
    std::vector<char> inside(n), outside(n);
    for (std::size_t i = 0; i < n; ++i) {
        inside[i] = view.coverage.size() == n ? view.coverage[i] >= 0.5f : 1;
        outside[i] = !inside[i];
    }
    const std::vector<float> d_out = squared_edt(outside, w, h);
    std::vector<char> valid(n), weak(n);
    for (std::size_t i = 0; i < n; ++i) valid[i] = inside[i] && d_out[i] > opt.erode_px * opt.erode_px;
    if (opt.strip_lines) {
        const std::vector<char> ink = find_ink(img, inside, opt.line_width, opt.line_contrast);
        for (std::size_t i = 0; i < n; ++i)
            if (ink[i]) {
                vc.line_pixels += inside[i] ? 1 : 0;
                valid[i] = 0;
            }
    }
    for (std::size_t i = 0; i < n; ++i) weak[i] = !valid[i];
    // Occlusion edges of the mesh in this view: a surface behind another one ends there,
    // so the view's say fades out before it.
    if (depth && depth->width == w && depth->height == h)
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const std::size_t i = std::size_t(y) * w + x;
                if (!depth->covered(x, y)) continue;
                const int nx[4] = {x - 1, x + 1, x, x}, ny[4] = {y, y, y - 1, y + 1};
                for (int k = 0; k < 4; ++k) {
                    if (nx[k] < 0 || ny[k] < 0 || nx[k] >= w || ny[k] >= h) continue;
                    const std::size_t j = std::size_t(ny[k]) * w + nx[k];
                    if (!depth->covered(nx[k], ny[k]) || std::abs(depth->depth[j] - depth->depth[i]) > depth_jump) {
                        weak[i] = 1;
                        break;
                    }
                }
            }
    const std::vector<float> d_weak = squared_edt(weak, w, h);
    for (std::size_t i = 0; i < n; ++i)
        vc.confidence[i] =
            valid[i] ? std::clamp((std::sqrt(d_weak[i]) - 0.5f) / std::max(opt.blend_px, 0.5f), 0.0f, 1.0f) : 0.0f;
    // Every other pixel takes the colour of the nearest valid one (breadth first, 8-connected).
    std::vector<std::uint32_t> queue;
    queue.reserve(n);
    std::vector<char> done(n, 0);
    for (std::size_t i = 0; i < n; ++i)
        if (valid[i]) {
            const int x = int(i % std::size_t(w)), y = int(i / std::size_t(w));
            vc.rgb[i] = {img.at(x, y, 0), img.at(x, y, std::min(1, img.channels - 1)),
                         img.at(x, y, std::min(2, img.channels - 1))};
            done[i] = 1;
            queue.push_back(std::uint32_t(i));
        }
    vc.any_valid = !queue.empty();
    if (!vc.any_valid) {
        for (std::size_t i = 0; i < n; ++i) {
            const int x = int(i % std::size_t(w)), y = int(i / std::size_t(w));
            vc.rgb[i] = {img.at(x, y, 0), img.at(x, y, std::min(1, img.channels - 1)),
                         img.at(x, y, std::min(2, img.channels - 1))};
        }
        return vc;
    }
    for (std::size_t q = 0; q < queue.size(); ++q) {
        const std::uint32_t i = queue[q];
        const int x = int(i % std::uint32_t(w)), y = int(i / std::uint32_t(w));
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int xx = x + dx, yy = y + dy;
                if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
                const std::size_t j = std::size_t(yy) * w + xx;
                if (done[j]) continue;
                done[j] = 1;
                vc.rgb[j] = vc.rgb[i];
                queue.push_back(std::uint32_t(j));
            }
    }
    return vc;
}

void ViewColours::sample(double x, double y, std::array<float, 3>& c, float& conf) const {
    const double fx = std::clamp(x - 0.5, 0.0, double(width - 1)), fy = std::clamp(y - 0.5, 0.0, double(height - 1));
    const int x0 = int(fx), y0 = int(fy);
    const int x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
    const float ax = float(fx - x0), ay = float(fy - y0);
    const float wts[4] = {(1 - ax) * (1 - ay), ax * (1 - ay), (1 - ax) * ay, ax * ay};
    const std::size_t idx[4] = {std::size_t(y0) * width + x0, std::size_t(y0) * width + x1,
                                std::size_t(y1) * width + x0, std::size_t(y1) * width + x1};
    c = {0, 0, 0};
    conf = 0;
    for (int k = 0; k < 4; ++k) {
        for (int ch = 0; ch < 3; ++ch) c[ch] += wts[k] * rgb[idx[k]][ch];
        conf += wts[k] * confidence[idx[k]];
    }
}

} // namespace cm
