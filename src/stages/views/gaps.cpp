#include "gaps.h"

#include <algorithm>
#include <cmath>

#include "geometry/distance_transform.h"

namespace cm {

double default_close_gaps(int w, int h) { return std::max(3.0, 0.004 * double(std::max(w, h))); }

std::vector<char> close_ink(const std::vector<char>& ink, int w, int h, double gap) {
    if (gap <= 0) return ink;
    const double radius = (gap + 1.0) / 2.0;
    const float r2 = float(radius * radius) + 1e-4f;
    // Padded by more than the radius, so the image border behaves as blank paper.
    const int pad = int(std::ceil(radius)) + 1;
    const int pw = w + 2 * pad, ph = h + 2 * pad;
    std::vector<char> seed(std::size_t(pw) * ph, 0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) seed[std::size_t(y + pad) * pw + x + pad] = ink[std::size_t(y) * w + x];
    // Dilation: within the radius of the ink.
    const std::vector<float> to_ink = squared_edt(seed, pw, ph);
    for (std::size_t i = 0; i < seed.size(); ++i) seed[i] = to_ink[i] > r2; // outside the dilation
    // Erosion of the dilation: farther than the radius from anything outside it.
    const std::vector<float> to_outside = squared_edt(seed, pw, ph);
    std::vector<char> closed(std::size_t(w) * h, 0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            closed[i] = ink[i] || to_outside[std::size_t(y + pad) * pw + x + pad] > r2;
        }
    return closed;
}

} // namespace cm
