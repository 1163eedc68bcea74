#include "drawing/fill.h"

#include <algorithm>
#include <cmath>

#include "drawing/ink.h"

namespace cm {

namespace {

// Running sums over a window of 2r+1 along rows, then along columns (zero outside the
// image), for `planes` interleaved planes.
std::vector<double> box_sum(const std::vector<double>& in, int w, int h, int planes, int r) {
    std::vector<double> tmp(in.size(), 0.0), out(in.size(), 0.0);
    std::vector<double> acc(static_cast<std::size_t>(planes), 0.0);
    for (int y = 0; y < h; ++y) {
        std::fill(acc.begin(), acc.end(), 0.0);
        const std::size_t row = std::size_t(y) * w;
        for (int x = -r; x < w; ++x) {
            if (x + r < w)
                for (int p = 0; p < planes; ++p) acc[p] += in[(row + x + r) * planes + p];
            if (x - r - 1 >= 0)
                for (int p = 0; p < planes; ++p) acc[p] -= in[(row + x - r - 1) * planes + p];
            if (x >= 0)
                for (int p = 0; p < planes; ++p) tmp[(row + x) * planes + p] = acc[p];
        }
    }
    for (int x = 0; x < w; ++x) {
        std::fill(acc.begin(), acc.end(), 0.0);
        for (int y = -r; y < h; ++y) {
            if (y + r < h)
                for (int p = 0; p < planes; ++p) acc[p] += tmp[(std::size_t(y + r) * w + x) * planes + p];
            if (y - r - 1 >= 0)
                for (int p = 0; p < planes; ++p) acc[p] -= tmp[(std::size_t(y - r - 1) * w + x) * planes + p];
            if (y >= 0)
                for (int p = 0; p < planes; ++p) out[(std::size_t(y) * w + x) * planes + p] = acc[p];
        }
    }
    return out;
}

} // namespace

std::vector<char> find_paper_slivers(const Image& img, const std::vector<char>& inside,
                                     const std::array<float, 3>& paper, float width, float contrast,
                                     float paper_distance) {
    const int w = img.width, h = img.height;
    // A thin light feature is a thin dark one of the negative: the ink finder's black top-hat
    // of the inverted image is the white top-hat of the image.
    Image neg;
    neg.width = w;
    neg.height = h;
    neg.channels = 3;
    neg.pixels.resize(std::size_t(w) * h * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) neg.at(x, y, c) = 1.0f - img.at(x, y, c);
    std::vector<char> light = find_ink(neg, inside, width, contrast, false);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            char& l = light[std::size_t(y) * w + x];
            if (!l) continue;
            double d2 = 0;
            for (int c = 0; c < 3; ++c)
                d2 += (img.at(x, y, c) - paper[std::size_t(c)]) * (img.at(x, y, c) - paper[std::size_t(c)]);
            l = d2 <= double(paper_distance) * paper_distance;
        }
    return light;
}

std::vector<char> find_pale_streaks(const Image& img, const std::vector<char>& inside,
                                    const std::vector<std::array<float, 3>>& fill, const std::array<float, 3>& paper,
                                    float width, float toward, float min_step, float density, float paper_distance,
                                    float paper_part) {
    const int w = img.width, h = img.height;
    const std::size_t n = std::size_t(w) * h;
    // The log of each pixel's distance to the paper: a thin dip of it is a thin feature
    // nearer the paper than what lies on both sides, by at least `toward` of their distance
    // (the ink finder's black top-hat of it). A step between two fills is no dip.
    Image near;
    near.width = w;
    near.height = h;
    near.channels = 1;
    near.pixels.resize(n);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double d2 = 0;
            for (int c = 0; c < 3; ++c)
                d2 += (img.at(x, y, c) - paper[std::size_t(c)]) * (img.at(x, y, c) - paper[std::size_t(c)]);
            near.pixels[std::size_t(y) * w + x] = float(std::log(std::sqrt(d2) + 0.02));
        }
    std::vector<char> pale = find_ink(near, inside, width, float(-std::log(1.0 - toward)), false);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            char& p = pale[std::size_t(y) * w + x];
            if (!p) continue;
            // On the way from the fill to the paper: the step from the fill mostly along it.
            const auto& m = fill[std::size_t(y) * w + x];
            double along = 0, len2 = 0, step2 = 0;
            for (int c = 0; c < 3; ++c) {
                const double v = paper[std::size_t(c)] - m[std::size_t(c)], d = img.at(x, y, c) - m[std::size_t(c)];
                along += v * d;
                len2 += v * v;
                step2 += d * d;
            }
            const double t = len2 > 1e-6 ? along / len2 : 0.0;
            const double across2 = std::max(0.0, step2 - t * t * len2); // off the way to the paper
            p = t >= toward && step2 >= double(min_step) * min_step && across2 <= 0.25 * t * t * len2;
        }
    // Beside the paper showing (within 1.5 `width` of a pixel within `paper_distance` of the
    // paper, or nearer it than `paper_part` of its fill's distance), a pale pixel is the blend
    // of a stroke's edge with the paper between strokes: hatching, whose paper is the
    // drawing's lightness as drawn, not a dry streak. A marker's dry streak lies between
    // strokes that cover the paper.
    const int reach = int(std::ceil(1.5 * width));
    std::vector<double> papery(n, 0.0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            if (!inside[i]) continue;
            double d2 = 0;
            for (int c = 0; c < 3; ++c)
                d2 += (img.at(x, y, c) - paper[std::size_t(c)]) * (img.at(x, y, c) - paper[std::size_t(c)]);
            double f2 = 0;
            for (int c = 0; c < 3; ++c)
                f2 += (fill[i][std::size_t(c)] - paper[std::size_t(c)]) *
                      (fill[i][std::size_t(c)] - paper[std::size_t(c)]);
            papery[i] = d2 <= std::max(double(paper_distance) * paper_distance, double(paper_part) * paper_part * f2);
        }
    papery = box_sum(papery, w, h, 1, reach);
    for (std::size_t i = 0; i < n; ++i) pale[i] = pale[i] && papery[i] == 0;
    // A marker's dry streaks repeat across its fill: at least `density` of the square of side
    // 4 `width` + 1 around. A lone thin light feature (a lit edge of shading drawn beside a
    // line or a shadow) is not a streak pattern and stays.
    const int r = int(std::ceil(2 * width));
    std::vector<double> counts(n);
    for (std::size_t i = 0; i < n; ++i) counts[i] = pale[i] ? 1.0 : 0.0;
    counts = box_sum(counts, w, h, 1, r);
    const double least = double(density) * (2 * r + 1) * (2 * r + 1);
    for (std::size_t i = 0; i < n; ++i) pale[i] = pale[i] && counts[i] >= least;
    return pale;
}

void keep_neutral_ink(const Image& img, std::vector<char>& ink, float max_chroma) {
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            char& k = ink[std::size_t(y) * img.width + x];
            if (!k) continue;
            const float r = img.at(x, y, 0), g = img.at(x, y, 1), b = img.at(x, y, 2);
            k = std::max({r, g, b}) - std::min({r, g, b}) < max_chroma;
        }
}

std::array<float, 3> paper_colour(const Image& img, const std::vector<char>& inside) {
    double s[3] = {0, 0, 0}, n = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            if (inside[std::size_t(y) * img.width + x]) continue;
            for (int c = 0; c < 3; ++c) s[c] += img.at(x, y, c);
            n += 1;
        }
    if (n == 0) return {1.0f, 1.0f, 1.0f};
    return {float(s[0] / n), float(s[1] / n), float(s[2] / n)};
}

std::vector<std::array<float, 3>> fill_under_strokes(const Image& img, const std::vector<char>& keep,
                                                     const std::vector<char>& strokes, int radius,
                                                     std::vector<float>& share) {
    const int w = img.width, h = img.height;
    const std::size_t n = std::size_t(w) * h;
    // Planes: the kept pixels' colour sum, their count, the strokes' count and the pixels'.
    std::vector<double> planes(n * 6, 0.0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            if (keep[i]) {
                for (int c = 0; c < 3; ++c) planes[i * 6 + c] = img.at(x, y, c);
                planes[i * 6 + 3] = 1;
            }
            planes[i * 6 + 4] = strokes[i] ? 1 : 0;
            planes[i * 6 + 5] = 1;
        }
    const std::vector<double> sums = box_sum(planes, w, h, 6, std::max(0, radius));
    std::vector<std::array<float, 3>> out(n);
    share.assign(n, 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            const double kept = sums[i * 6 + 3];
            share[i] = float(sums[i * 6 + 4] / std::max(1.0, sums[i * 6 + 5]));
            if (kept <= 0) {
                out[i] = {img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2)};
                continue;
            }
            for (int c = 0; c < 3; ++c) out[i][std::size_t(c)] = float(sums[i * 6 + c] / kept);
        }
    return out;
}

} // namespace cm
