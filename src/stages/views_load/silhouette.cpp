#include "silhouette.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <sstream>

#include "core/error.h"

namespace cm {

namespace {

using Rgb = std::array<float, 3>;

float dist(const Rgb& a, const Rgb& b) {
    const float dr = a[0] - b[0], dg = a[1] - b[1], db = a[2] - b[2];
    return std::sqrt((dr * dr + dg * dg + db * db) / 3.0f);
}

Rgb parse_colour(const std::string& s) {
    if (s == "white") return {1, 1, 1};
    if (s == "black") return {0, 0, 0};
    if (s.size() == 7 && s[0] == '#') {
        Rgb c{};
        for (int k = 0; k < 3; ++k) c[k] = float(std::stoi(s.substr(1 + 2 * k, 2), nullptr, 16)) / 255.0f;
        return c;
    }
    std::stringstream ss(s);
    Rgb c{};
    char comma;
    if (ss >> c[0] >> comma >> c[1] >> comma >> c[2]) {
        for (auto& x : c) x /= 255.0f;
        return c;
    }
    throw Error("background \"" + s + "\" is not auto, alpha, white, black, #rrggbb or r,g,b");
}

// Component labelling (4-connected) of mask; returns labels and sizes.
int label(const std::vector<char>& mask, int w, int h, std::vector<int>& lab, std::vector<std::size_t>& sizes) {
    lab.assign(mask.size(), -1);
    sizes.clear();
    std::vector<int> stack;
    for (int start = 0; start < w * h; ++start) {
        if (!mask[start] || lab[start] >= 0) continue;
        const int id = int(sizes.size());
        sizes.push_back(0);
        stack.push_back(start);
        lab[start] = id;
        while (!stack.empty()) {
            const int p = stack.back();
            stack.pop_back();
            ++sizes[id];
            const int x = p % w, y = p / w;
            const int nb[4] = {x > 0 ? p - 1 : -1, x + 1 < w ? p + 1 : -1, y > 0 ? p - w : -1, y + 1 < h ? p + w : -1};
            for (int q : nb)
                if (q >= 0 && mask[q] && lab[q] < 0) { lab[q] = id; stack.push_back(q); }
        }
    }
    return int(sizes.size());
}

} // namespace

SilhouetteResult extract_silhouette(const Image& img, const ImageInfo& info, const SilhouetteOptions& opt) {
    const int w = img.width, h = img.height;
    const std::size_t n = std::size_t(w) * h;
    SilhouetteResult res;
    res.coverage.assign(n, 0.0f);

    bool use_alpha = opt.background == "alpha";
    if (opt.background == "auto" && info.has_alpha) {
        // Alpha is meaningful when part of the image is transparent.
        std::size_t transparent = 0;
        for (std::size_t i = 0; i < n; ++i) transparent += img.pixels[i * 4 + 3] < 0.5f;
        use_alpha = transparent > 0 && transparent < n;
    }
    if (use_alpha) {
        res.method = "alpha";
        for (std::size_t i = 0; i < n; ++i) res.coverage[i] = std::clamp(img.pixels[i * 4 + 3], 0.0f, 1.0f);
    } else {
        res.method = "background";
        // Background colour and spread from the border (median and median absolute deviation).
        std::vector<Rgb> border;
        auto px = [&](int x, int y) { const float* p = &img.pixels[(std::size_t(y) * w + x) * 4]; return Rgb{p[0], p[1], p[2]}; };
        for (int x = 0; x < w; ++x) { border.push_back(px(x, 0)); border.push_back(px(x, h - 1)); }
        for (int y = 0; y < h; ++y) { border.push_back(px(0, y)); border.push_back(px(w - 1, y)); }
        Rgb bg{};
        if (opt.background == "auto") {
            for (int k = 0; k < 3; ++k) {
                std::vector<float> c(border.size());
                for (std::size_t i = 0; i < border.size(); ++i) c[i] = border[i][k];
                std::nth_element(c.begin(), c.begin() + c.size() / 2, c.end());
                bg[k] = c[c.size() / 2];
            }
        } else {
            bg = parse_colour(opt.background);
        }
        std::vector<float> bd(border.size());
        for (std::size_t i = 0; i < border.size(); ++i) bd[i] = dist(border[i], bg);
        std::nth_element(bd.begin(), bd.begin() + bd.size() / 2, bd.end());
        const float spread = bd[bd.size() / 2];
        const float t = opt.threshold > 0 ? float(opt.threshold) : std::clamp(6.0f * spread + 0.08f, 0.1f, 0.5f);
        res.threshold = t;
        std::vector<float> d(n);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) d[std::size_t(y) * w + x] = dist(px(x, y), bg);
        // Background: pixels near the background colour connected to the border.
        std::vector<char> bgmask(n, 0);
        std::deque<int> q;
        auto seed = [&](int p) { if (!bgmask[p] && d[p] < t) { bgmask[p] = 1; q.push_back(p); } };
        for (int x = 0; x < w; ++x) { seed(x); seed((h - 1) * w + x); }
        for (int y = 0; y < h; ++y) { seed(y * w); seed(y * w + w - 1); }
        while (!q.empty()) {
            const int p = q.front();
            q.pop_front();
            const int x = p % w, y = p / w;
            if (x > 0) seed(p - 1);
            if (x + 1 < w) seed(p + 1);
            if (y > 0) seed(p - w);
            if (y + 1 < h) seed(p + w);
        }
        // Coverage: 1 inside; along the boundary, a ramp on the colour distance keeps anti-aliasing.
        std::vector<float> objd;
        for (std::size_t i = 0; i < n; ++i)
            if (!bgmask[i]) objd.push_back(d[i]);
        float dref = 2 * t;
        if (!objd.empty()) {
            std::nth_element(objd.begin(), objd.begin() + objd.size() / 2, objd.end());
            dref = std::max(objd[objd.size() / 2], 1.5f * t);
        }
        for (std::size_t i = 0; i < n; ++i) {
            if (!bgmask[i]) res.coverage[i] = 1.0f;
            else res.coverage[i] = std::clamp(0.5f * d[i] / t, 0.0f, 0.49f);
        }
        // Object pixels next to background with a weak colour get fractional coverage.
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const std::size_t i = std::size_t(y) * w + x;
                if (bgmask[i]) continue;
                const bool edge = (x > 0 && bgmask[i - 1]) || (x + 1 < w && bgmask[i + 1]) || (y > 0 && bgmask[i - w]) ||
                                  (y + 1 < h && bgmask[i + w]);
                if (edge && d[i] < dref) res.coverage[i] = 0.5f + 0.5f * std::clamp((d[i] - t) / (dref - t), 0.0f, 1.0f);
            }
        // Tiny background-coloured flecks inside are object (already: they are not connected to the border).
    }

    // Components: drop specks and separate marks a user would not keep.
    if (opt.keep != "all") {
        std::vector<char> mask(n);
        for (std::size_t i = 0; i < n; ++i) mask[i] = res.coverage[i] >= 0.5f;
        std::vector<int> lab;
        std::vector<std::size_t> sizes;
        const int nc = label(mask, w, h, lab, sizes);
        if (nc > 0) {
            const std::size_t largest = *std::max_element(sizes.begin(), sizes.end());
            std::vector<char> keep(std::size_t(nc), 0);
            for (int c = 0; c < nc; ++c) {
                if (opt.keep == "largest") keep[c] = sizes[c] == largest;
                else keep[c] = double(sizes[c]) >= 0.05 * double(largest);
            }
            for (int c = 0; c < nc; ++c) (keep[c] ? res.components_kept : res.components_dropped)++;
            for (std::size_t i = 0; i < n; ++i)
                if (lab[i] >= 0 && !keep[lab[i]]) res.coverage[i] = 0.0f;
            // Fractional coverage next to dropped components goes too.
            for (std::size_t i = 0; i < n; ++i)
                if (res.coverage[i] < 0.5f) {
                    const int x = int(i % w), y = int(i / w);
                    bool near_kept = false;
                    for (int dy = -1; dy <= 1 && !near_kept; ++dy)
                        for (int dx = -1; dx <= 1; ++dx) {
                            const int xx = x + dx, yy = y + dy;
                            if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
                            const int l = lab[std::size_t(yy) * w + xx];
                            if (l >= 0 && keep[l]) { near_kept = true; break; }
                        }
                    if (!near_kept) res.coverage[i] = 0.0f;
                }
        }
    }
    return res;
}

} // namespace cm
