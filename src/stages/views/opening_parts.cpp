#include "opening_parts.h"

#include <algorithm>

#include "line_holes.h"

namespace cm {

std::vector<char> parts_seen_through(const std::vector<int>& region, int count, const std::vector<char>& kind,
                                     const std::vector<char>& barrier, const std::vector<char>& bg, int w, int h) {
    std::vector<char> part(std::size_t(count), 0);
    std::vector<std::size_t> area(std::size_t(count), 0);
    for (const int r : region)
        if (r >= 0) ++area[std::size_t(r)];
    const RegionLinks links = link_regions(region, count, barrier, bg, w, h);
    std::vector<std::size_t> rims(std::size_t(count), 0);
    for (std::size_t r = 0; r < std::size_t(count); ++r) {
        rims[r] = links.outside[r];
        for (const auto& [b, length] : links.beside[r]) rims[r] += length;
    }
    // The area to the strokes' centre lines: the blank area and half a pixel per rim pixel
    // (the strokes' width is the same on both sides of the shared line, so it cancels).
    auto centred = [&](std::size_t r) { return double(area[r]) + 0.5 * double(rims[r]); };
    for (std::size_t r = 0; r < std::size_t(count); ++r) {
        if (kind[r] == kNestedInside || rims[r] == 0) continue;
        for (const auto& [b, length] : links.beside[r]) {
            const std::size_t o = std::size_t(b);
            if (kind[o] == kNestedInside || 4 * length < rims[r]) continue;
            if (2 * centred(r) <= centred(o)) part[r] = 1;
        }
    }
    return part;
}

std::size_t open_hole_tips(std::vector<char>& bg, const std::vector<char>& ink, const std::vector<char>& closed,
                           const std::vector<int>& region, const std::vector<char>& hole,
                           const std::vector<char>& candidate, int w, int h) {
    const std::size_t n = std::size_t(w) * h;
    // Owner per pixel: a region's label, kOutside, or kFree where the closing's pixels off the
    // ink are still to be reached (kWall elsewhere: ink, never reached).
    constexpr int kOutside = -2, kFree = -1, kWall = -3;
    std::vector<int> owner(n, kWall), holes_front, others_front;
    std::vector<std::size_t> area(hole.size(), 0);
    std::size_t body = 0;
    bool any = false;
    for (std::size_t i = 0; i < n; ++i) {
        const int r = region[i];
        body += !bg[i] || (r >= 0 && hole[std::size_t(r)]);
        if (r >= 0) {
            owner[i] = r;
            ++area[std::size_t(r)];
            (hole[std::size_t(r)] ? holes_front : others_front).push_back(int(i));
            any = any || hole[std::size_t(r)];
        } else if (bg[i]) {
            owner[i] = kOutside;
            others_front.push_back(int(i));
        } else if (closed[i] && !ink[i]) {
            owner[i] = kFree;
        }
    }
    if (!any) return 0;
    auto each4 = [&](int p, auto&& f) {
        const int x = p % w, y = p / w;
        if (x > 0) f(p - 1);
        if (x + 1 < w) f(p + 1);
        if (y > 0) f(p - w);
        if (y + 1 < h) f(p + w);
    };
    std::vector<int> next;
    auto step = [&](std::vector<int>& front) {
        next.clear();
        for (const int p : front)
            each4(p, [&](int q) {
                if (owner[std::size_t(q)] != kFree) return;
                owner[std::size_t(q)] = owner[std::size_t(p)];
                next.push_back(q);
            });
        front.swap(next);
    };
    // Layer by layer, the others first: a pixel as near to both stays closed.
    while (!holes_front.empty() || !others_front.empty()) {
        step(others_front);
        step(holes_front);
    }
    // A region of the inside under a candidate's size (0.25 % of the drawing; no candidate:
    // those are judged on their own) whose paper meets the opened holes' alone lies in a tip
    // of one (paper the closing left between converging lines).
    std::vector<char> meets_hole(hole.size(), 0), meets_other(hole.size(), 0);
    auto opened = [&](int o) { return o >= 0 && hole[std::size_t(o)]; };
    for (std::size_t i = 0; i < n; ++i) {
        const int a = owner[i];
        if (a < 0 || hole[std::size_t(a)]) continue;
        each4(int(i), [&](int q) {
            const int b = owner[std::size_t(q)];
            if (b == a || b == kWall || b == kFree) return;
            (opened(b) ? meets_hole : meets_other)[std::size_t(a)] = 1;
        });
    }
    std::size_t given = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const int a = owner[i];
        if (a < 0) continue;
        const bool tip = !hole[std::size_t(a)] && !candidate[std::size_t(a)] && meets_hole[std::size_t(a)] &&
                         !meets_other[std::size_t(a)] && 400 * area[std::size_t(a)] < body;
        if ((hole[std::size_t(a)] && region[i] < 0) || tip) {
            given += !bg[i];
            bg[i] = 1;
        }
    }
    return given;
}

} // namespace cm
