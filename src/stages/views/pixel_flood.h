// Flood fills over a w x h pixel grid (row-major, row 0 at the top), shared by the
// silhouette steps: from the image border through what may be passed, and 8-connected
// pieces grown from a seed.
#pragma once
#include <algorithm>
#include <cstddef>
#include <vector>

namespace cm {

/// Scanline fill of the piece holding `start` through the pixels for which `open(p)` holds:
/// each seed's whole run of open pixels along its row goes to `take_run(row, l, r)` (row
/// start, first and last column), which must make them no longer open; the seed then leaves
/// one seed for each run of open pixels in that stretch of the rows above and below, widened
/// by a pixel each way when `eight` (diagonal neighbours). The same pixels as a fill pixel by
/// pixel, with a stack entry per run instead of per pixel. `stack` is scratch.
template <typename Open, typename TakeRun>
void scanline_fill(int w, int h, int start, bool eight, std::vector<int>& stack, Open&& open, TakeRun&& take_run) {
    stack.push_back(start);
    while (!stack.empty()) {
        const int p = stack.back();
        stack.pop_back();
        if (!open(p)) continue;
        const int y = p / w, row = y * w;
        int l = p - row, r = l;
        while (l > 0 && open(row + l - 1)) --l;
        while (r + 1 < w && open(row + r + 1)) ++r;
        take_run(row, l, r);
        const int a = eight ? std::max(0, l - 1) : l, b = eight ? std::min(w - 1, r + 1) : r;
        for (const int ny : {y - 1, y + 1}) {
            if (ny < 0 || ny >= h) continue;
            const int nrow = ny * w;
            bool in_run = false;
            for (int x = a; x <= b; ++x) {
                const bool o = open(nrow + x);
                if (o && !in_run) stack.push_back(nrow + x);
                in_run = o;
            }
        }
    }
}

/// Marks in `reached` every pixel 4-connected to the image border through pixels for which
/// `passable(p)` holds (and `reached` is not yet set): scanline_fill from each border pixel,
/// in row order.
template <typename Passable>
void flood_from_border(int w, int h, std::vector<char>& reached, Passable passable) {
    auto open = [&](int p) { return !reached[std::size_t(p)] && passable(p); };
    auto take = [&](int row, int l, int r) {
        std::fill(reached.begin() + row + l, reached.begin() + row + r + 1, char(1));
    };
    std::vector<int> stack;
    auto seed = [&](int p) { scanline_fill(w, h, p, false, stack, open, take); };
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
