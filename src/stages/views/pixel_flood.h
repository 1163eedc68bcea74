// Flood fills over a w x h pixel grid (row-major, row 0 at the top), shared by the
// silhouette steps: from the image border through what may be passed, and 8-connected
// pieces grown from a seed.
#pragma once
#include <algorithm>
#include <cstddef>
#include <vector>

namespace cm {

/// Marks in `reached` every pixel 4-connected to the image border through pixels for which
/// `passable(p)` holds (and `reached` is not yet set).
///
/// Scanline fill: a seed fills its whole run of open pixels along the row, then leaves one
/// seed for each run of open pixels in that stretch of the rows above and below. The same
/// pixels as a flood pixel by pixel (the 4-connected component of the open pixels that
/// holds the border's), in row order and with a stack entry per run instead of per pixel.
template <typename Passable>
void flood_from_border(int w, int h, std::vector<char>& reached, Passable passable) {
    auto open = [&](int p) { return !reached[std::size_t(p)] && passable(p); };
    std::vector<int> stack;
    auto fill = [&](int p) {
        const int y = p / w, row = y * w;
        int l = p - row, r = l;
        while (l > 0 && open(row + l - 1)) --l;
        while (r + 1 < w && open(row + r + 1)) ++r;
        std::fill(reached.begin() + row + l, reached.begin() + row + r + 1, char(1));
        for (const int ny : {y - 1, y + 1}) {
            if (ny < 0 || ny >= h) continue;
            const int nrow = ny * w;
            bool in_run = false;
            for (int x = l; x <= r; ++x) {
                const bool o = open(nrow + x);
                if (o && !in_run) stack.push_back(nrow + x);
                in_run = o;
            }
        }
    };
    auto seed = [&](int p) {
        if (!open(p)) return;
        fill(p);
        while (!stack.empty()) {
            const int q = stack.back();
            stack.pop_back();
            if (open(q)) fill(q);
        }
    };
    for (int x = 0; x < w; ++x) {
        seed(x);
        seed((h - 1) * w + x);
    }
    for (int y = 0; y < h; ++y) {
        seed(y * w);
        seed(y * w + w - 1);
    }
}

/// Grows the 8-connected piece of `start` (which the caller has taken already): `take(q)`
/// is asked for each neighbour and returns true when q joins (marking it taken);
/// `visit(p)` is called for every pixel of the piece, `start` included.
template <typename Take, typename Visit>
void grow_piece_8(int start, int w, int h, Take take, Visit visit) {
    std::vector<int> stack{start};
    while (!stack.empty()) {
        const int p = stack.back();
        stack.pop_back();
        visit(p);
        const int x = p % w, y = p / w;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int xx = x + dx, yy = y + dy;
                if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
                const int q = yy * w + xx;
                if (take(q)) stack.push_back(q);
            }
    }
}

/// `img` with `pad` pixels of `outside` around it: (w + 2 pad) x (h + 2 pad).
inline std::vector<char> padded(const std::vector<char>& img, int w, int h, int pad, char outside) {
    const int pw = w + 2 * pad;
    std::vector<char> out(std::size_t(pw) * (h + 2 * pad), outside);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) out[std::size_t(y + pad) * pw + x + pad] = img[std::size_t(y) * w + x];
    return out;
}

} // namespace cm
