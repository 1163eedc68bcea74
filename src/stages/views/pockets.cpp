#include "pockets.h"

#include <vector>

#include "components.h"
#include "silhouette_holes.h"

namespace cm {

std::size_t fill_pockets(Coverage& cov) {
    const int w = cov.window_width(), h = cov.window_height();
    if (w <= 2 || h <= 2) return 0; // no pixel of the window is enclosed
    const std::vector<float>& values = cov.window_values();
    const std::size_t n = values.size();
    std::vector<char> under(n);
    for (std::size_t i = 0; i < n; ++i) under[i] = values[i] < 0.5f;
    std::vector<int> lab;
    std::vector<std::size_t> sizes;
    const int count = mask_components(under, w, h, true, lab, sizes);
    // A region touching the window's edge meets the zeros beyond it (or the image's border):
    // the background reaches it.
    std::vector<char> reached(std::size_t(count), 0);
    for (int x = 0; x < w; ++x)
        for (const int y : {0, h - 1})
            if (const int l = lab[std::size_t(y) * w + x]; l >= 0) reached[std::size_t(l)] = 1;
    for (int y = 0; y < h; ++y)
        for (const int x : {0, w - 1})
            if (const int l = lab[std::size_t(y) * w + x]; l >= 0) reached[std::size_t(l)] = 1;
    // A pocket's paper: its pixels' uncovered shares summed, the area a blank region of the
    // same paper would have (its pixels wholly uncovered).
    std::vector<double> paper(std::size_t(count), 0.0);
    for (std::size_t i = 0; i < n; ++i)
        if (lab[i] >= 0) paper[std::size_t(lab[i])] += 1.0 - double(values[i]);
    std::vector<char> pocket(std::size_t(count), 0);
    std::size_t filled = 0;
    for (std::size_t l = 0; l < std::size_t(count); ++l) {
        pocket[l] = !reached[l] && paper[l] < double(kStrokeGapArea);
        filled += pocket[l];
    }
    if (filled == 0) return 0;
    std::vector<float> out = values;
    for (std::size_t i = 0; i < n; ++i)
        if (lab[i] >= 0 && pocket[std::size_t(lab[i])]) out[i] = 1.0f;
    cov = Coverage::of_window(std::move(out), cov.width(), cov.height(), cov.x0(), cov.y0(), w, h);
    return filled;
}

} // namespace cm
