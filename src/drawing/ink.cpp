#include "drawing/ink.h"

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

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

std::vector<char> find_ink(const Image& img, const std::vector<char>& inside, float line_width, float line_contrast,
                           bool fringe) {
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
    return fringe ? grow_ink(ink, inside, w, h) : ink;
}

std::vector<char> grow_ink(const std::vector<char>& ink, const std::vector<char>& inside, int w, int h) {
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

} // namespace cm
