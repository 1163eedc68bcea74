#include "shadow.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

namespace cm {

namespace {

// Darker than the background with its hue: a shadow cast on it.
bool shadow_like(const float* p, const std::array<double, 3>& b) {
    const double lb = (b[0] + b[1] + b[2]) / 3.0;
    if (lb < 0.15) return false; // no shadow shows on a dark background
    const double s = ((p[0] + p[1] + p[2]) / 3.0) / lb;
    if (s < 0.35 || s > 0.97) return false;
    for (int k = 0; k < 3; ++k)
        if (std::abs(p[k] - s * b[std::size_t(k)]) > 0.06) return false;
    return true;
}

// The background's own colour (each channel within 0.06 of it): blank paper.
bool paper_like(const float* p, const std::array<double, 3>& b) {
    for (int k = 0; k < 3; ++k)
        if (std::abs(p[k] - b[std::size_t(k)]) > 0.06) return false;
    return true;
}

// How far (px) from blank paper a pencil line's core lies at most: half a 5 px line, or of
// lines merged side by side with slivers of paper between them, and the anti-aliased fringe.
constexpr int kStrokeCoreReach = 4;

struct Region {
    std::vector<int> pixels;
    int ymin = 1 << 30, ymax = -1;
    double ysum = 0;
    bool touches_bg = false;
};

} // namespace

std::size_t remove_ground_shadow(const Image& img, const BackgroundField& background, std::vector<char>& bg) {
    const int w = img.width, h = img.height;
    const std::size_t n = std::size_t(w) * h;
    std::vector<char> like(n, 0), core(n, 0);
    tbb::parallel_for(0, h, [&](int y) {
        for (std::size_t i = std::size_t(y) * w, e = i + std::size_t(w); i < e; ++i)
            like[i] = !bg[i] && shadow_like(img.rgba(i).data(), background.at(i));
    });
    // Nothing darker with the background's hue (a flat mask, most line art): no shadow, and
    // none of the passes below has anything to find.
    if (std::find(like.begin(), like.end(), char(1)) == like.end()) return 0;
    // Core: every 8-neighbour is shadow-like or background (not the object's anti-aliased rim).
    tbb::parallel_for(0, h, [&](int y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            bool ok = like[i] != 0;
            for (int dy = -1; dy <= 1 && ok; ++dy)
                for (int dx = -1; dx <= 1 && ok; ++dx) {
                    const int xx = std::clamp(x + dx, 0, w - 1), yy = std::clamp(y + dy, 0, h - 1);
                    const std::size_t j = std::size_t(yy) * w + xx;
                    ok = like[j] || bg[j];
                }
            core[i] = ok;
        }
    });
    // The object without the shadow-like cores: its rows.
    int oymin = 1 << 30, oymax = -1;
    for (std::size_t i = 0; i < n; ++i)
        if (!bg[i] && !core[i]) {
            oymin = std::min(oymin, int(i / std::size_t(w)));
            oymax = std::max(oymax, int(i / std::size_t(w)));
        }
    if (oymax < 0) return 0;
    const double oh = oymax - oymin + 1, ocentre = 0.5 * (oymin + oymax);
    // A grey pencil line has the paper's hue and is darker: shadow-like. Line art's lines
    // have the object's blank paper (enclosed, not background) within a few pixels of most of
    // their core, inside the outline or between merged lines; a ground shadow has it, if at
    // all, along its upper rim only, beyond the outline's stroke.
    auto beside_blank = [&](int p) {
        const int x = p % w, y = p / w, r = kStrokeCoreReach;
        for (int dy = -r; dy <= r; ++dy)
            for (int dx = -r; dx <= r; ++dx) {
                const int xx = x + dx, yy = y + dy;
                if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
                const std::size_t j = std::size_t(yy) * w + xx;
                if (!bg[j] && !like[j] && paper_like(img.rgba(j).data(), background.at(j))) return true;
            }
        return false;
    };
    auto is_line = [&](const Region& r) {
        const auto near = std::count_if(r.pixels.begin(), r.pixels.end(), beside_blank);
        return 2 * std::size_t(near) >= r.pixels.size();
    };
    std::vector<char> seen(n, 0), shadow(n, 0);
    std::vector<int> stack;
    for (std::size_t start = 0; start < n; ++start) {
        if (!core[start] || seen[start]) continue;
        Region r;
        stack.push_back(int(start));
        seen[start] = 1;
        while (!stack.empty()) {
            const int p = stack.back();
            stack.pop_back();
            r.pixels.push_back(p);
            const int x = p % w, y = p / w;
            r.ymin = std::min(r.ymin, y);
            r.ymax = std::max(r.ymax, y);
            r.ysum += y;
            const int nb[4][2] = {{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
            for (const auto& q : nb) {
                if (q[0] < 0 || q[1] < 0 || q[0] >= w || q[1] >= h) continue;
                const std::size_t j = std::size_t(q[1]) * w + q[0];
                r.touches_bg = r.touches_bg || bg[j];
                if (core[j] && !seen[j]) {
                    seen[j] = 1;
                    stack.push_back(int(j));
                }
            }
        }
        const double centre = r.ysum / double(r.pixels.size());
        const bool under =
            r.touches_bg && r.ymax >= oymax - 1 && centre > ocentre && double(r.ymax - r.ymin + 1) <= 0.5 * oh;
        if (under && !is_line(r))
            for (int p : r.pixels) shadow[std::size_t(p)] = 1;
    }
    // The shadow's soft rim: shadow-like pixels up to 2 px from it.
    std::size_t removed = 0;
    for (int pass = 0; pass < 3; ++pass) {
        std::vector<char> next = shadow;
        tbb::parallel_for(0, h, [&](int y) {
            for (int x = 0; x < w; ++x) {
                const std::size_t i = std::size_t(y) * w + x;
                if (shadow[i] || !like[i] || pass == 2) continue;
                const bool near = (x > 0 && shadow[i - 1]) || (x + 1 < w && shadow[i + 1]) ||
                                  (y > 0 && shadow[i - std::size_t(w)]) || (y + 1 < h && shadow[i + std::size_t(w)]);
                next[i] = near;
            }
        });
        shadow.swap(next);
    }
    for (std::size_t i = 0; i < n; ++i)
        if (shadow[i] && !bg[i]) {
            bg[i] = 1;
            ++removed;
        }
    return removed;
}

} // namespace cm
