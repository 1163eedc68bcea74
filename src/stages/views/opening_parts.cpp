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

} // namespace cm
