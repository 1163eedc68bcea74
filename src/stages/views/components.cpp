#include "components.h"

#include <algorithm>

#include <tbb/parallel_for.h>

#include "pixel_flood.h"

namespace cm {

namespace {

// Fractional coverage goes with the component it borders: clears it where no 8-neighbour
// belongs to a kept component.
void clear_stray_fringe(int w, int h, const std::vector<int>& lab, const std::vector<char>& keep,
                        std::vector<float>& cov) {
    tbb::parallel_for(0, h, [&](int y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            if (cov[i] >= 0.5f || cov[i] == 0.0f) continue;
            bool near_kept = false;
            for (int dy = -1; dy <= 1 && !near_kept; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
                    const int l = lab[std::size_t(yy) * w + xx];
                    if (l >= 0 && keep[std::size_t(l)]) {
                        near_kept = true;
                        break;
                    }
                }
            if (!near_kept) cov[i] = 0.0f;
        }
    });
}

} // namespace

int mask_components(const std::vector<char>& mask, int w, int h, bool eight, std::vector<int>& lab,
                    std::vector<std::size_t>& sizes) {
    lab.assign(mask.size(), -1);
    sizes.clear();
    auto open = [&](int p) { return mask[std::size_t(p)] && lab[std::size_t(p)] < 0; };
    std::vector<int> stack;
    for (int start = 0; start < w * h; ++start) {
        if (!open(start)) continue;
        const int id = int(sizes.size());
        sizes.push_back(0);
        scanline_fill(w, h, start, eight, stack, open, [&](int row, int l, int r) {
            std::fill(lab.begin() + row + l, lab.begin() + row + r + 1, id);
            sizes[std::size_t(id)] += std::size_t(r - l + 1);
        });
    }
    return int(sizes.size());
}

void keep_components(int w, int h, const std::string& mode, std::vector<float>& coverage, SilhouetteResult& res) {
    const std::size_t n = std::size_t(w) * h;
    std::vector<char> mask(n);
    for (std::size_t i = 0; i < n; ++i) mask[i] = coverage[i] >= 0.5f;
    std::vector<int> lab;
    std::vector<std::size_t> sizes;
    const int nc = mask_components(mask, w, h, true, lab, sizes);
    if (nc == 0 || mode == "all") {
        res.components_kept = nc;
        return;
    }
    const std::size_t largest = *std::max_element(sizes.begin(), sizes.end());
    std::vector<char> keep(std::size_t(nc), 0);
    bool largest_taken = false;
    for (int c = 0; c < nc; ++c) {
        if (mode == "largest") {
            keep[std::size_t(c)] = sizes[std::size_t(c)] == largest && !largest_taken;
            largest_taken |= keep[std::size_t(c)] != 0;
        } else {
            keep[std::size_t(c)] = double(sizes[std::size_t(c)]) >= 0.05 * double(largest);
        }
        (keep[std::size_t(c)] ? res.components_kept : res.components_dropped)++;
    }
    if (res.components_dropped == 0) return;
    for (std::size_t i = 0; i < n; ++i)
        if (lab[i] >= 0 && !keep[std::size_t(lab[i])]) coverage[i] = 0.0f;
    clear_stray_fringe(w, h, lab, keep, coverage);
}

} // namespace cm
