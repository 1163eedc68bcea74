#include "sheet.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "core/error.h"
#include "silhouette.h"

namespace fs = std::filesystem;

namespace cm {

namespace {

struct Box {
    int x0, y0, x1, y1; ///< [x0, x1) x [y0, y1)
    double area;
};

// Components of coverage >= 0.5, 8-connected: their boxes and areas.
std::vector<Box> components(const std::vector<float>& cov, int w, int h) {
    std::vector<int> lab(cov.size(), -1);
    std::vector<Box> boxes;
    std::vector<std::size_t> stack;
    for (std::size_t s = 0; s < cov.size(); ++s) {
        if (cov[s] < 0.5f || lab[s] >= 0) continue;
        const int id = int(boxes.size());
        Box b{w, h, 0, 0, 0};
        lab[s] = id;
        stack.push_back(s);
        while (!stack.empty()) {
            const std::size_t i = stack.back();
            stack.pop_back();
            const int x = int(i % std::size_t(w)), y = int(i / std::size_t(w));
            b = {std::min(b.x0, x), std::min(b.y0, y), std::max(b.x1, x + 1), std::max(b.y1, y + 1), b.area + 1};
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int nx = x + dx, ny = y + dy;
                    if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
                    const std::size_t j = std::size_t(ny) * w + nx;
                    if (cov[j] >= 0.5f && lab[j] < 0) {
                        lab[j] = id;
                        stack.push_back(j);
                    }
                }
        }
        boxes.push_back(b);
    }
    return boxes;
}

// Splits `boxes` at the gaps of at least `gap` pixels along x (axis 0) or y (axis 1);
// one group when there is none.
std::vector<std::vector<Box>> cut(std::vector<Box> boxes, int axis, int gap) {
    auto lo = [axis](const Box& b) { return axis == 0 ? b.x0 : b.y0; };
    auto hi = [axis](const Box& b) { return axis == 0 ? b.x1 : b.y1; };
    std::sort(boxes.begin(), boxes.end(), [&](const Box& a, const Box& b) { return lo(a) < lo(b); });
    std::vector<std::vector<Box>> groups;
    int reach = 0;
    for (const Box& b : boxes) {
        if (groups.empty() || lo(b) - reach >= gap) groups.emplace_back();
        groups.back().push_back(b);
        reach = groups.back().size() == 1 ? hi(b) : std::max(reach, hi(b));
    }
    return groups;
}

// Recursive XY-cut: the groups of boxes no blank band of `gap` pixels divides.
void xy_cut(const std::vector<Box>& boxes, int gap, std::vector<Box>& out) {
    for (int axis : {0, 1}) {
        const auto groups = cut(boxes, axis, gap);
        if (groups.size() > 1) {
            for (const auto& g : groups) xy_cut(g, gap, out);
            return;
        }
    }
    Box u = boxes.front();
    u.area = 0;
    for (const Box& b : boxes)
        u = {std::min(u.x0, b.x0), std::min(u.y0, b.y0), std::max(u.x1, b.x1), std::max(u.y1, b.y1), u.area + b.area};
    out.push_back(u);
}

// Left to right, then top to bottom: rows are panels whose vertical extents overlap.
void reading_order(std::vector<Box>& panels) {
    std::sort(panels.begin(), panels.end(), [](const Box& a, const Box& b) { return a.y0 < b.y0; });
    for (std::size_t i = 0; i < panels.size();) {
        std::size_t j = i + 1;
        int bottom = panels[i].y1;
        while (j < panels.size() && panels[j].y0 < bottom) bottom = std::max(bottom, panels[j++].y1);
        std::sort(panels.begin() + long(i), panels.begin() + long(j),
                  [](const Box& a, const Box& b) { return a.x0 < b.x0; });
        i = j;
    }
}

// Any ink (coverage > 0) in [x0, x1) x [y0, y1), clipped to the image.
bool ink_in(const std::vector<float>& cov, int w, int h, int x0, int y0, int x1, int y1) {
    for (int y = std::max(0, y0); y < std::min(h, y1); ++y)
        for (int x = std::max(0, x0); x < std::min(w, x1); ++x)
            if (cov[std::size_t(y) * w + x] > 0.0f) return true;
    return false;
}

// The panel's box grown ring by ring into blank paper: each side stops at the image border,
// at ink that is not the panel's, or at `margin` pixels.
SheetPanel grow(const std::vector<float>& cov, int w, int h, const Box& b, int margin) {
    int x0 = std::max(0, b.x0 - 2), y0 = std::max(0, b.y0 - 2); // the drawing's anti-aliased fringe
    int x1 = std::min(w, b.x1 + 2), y1 = std::min(h, b.y1 + 2);
    bool left = true, right = true, top = true, bottom = true;
    for (int step = 0; step < margin && (left || right || top || bottom); ++step) {
        left = left && x0 > 0 && !ink_in(cov, w, h, x0 - 1, y0, x0, y1);
        if (left) --x0;
        right = right && x1 < w && !ink_in(cov, w, h, x1, y0, x1 + 1, y1);
        if (right) ++x1;
        top = top && y0 > 0 && !ink_in(cov, w, h, x0, y0 - 1, x1, y0);
        if (top) --y0;
        bottom = bottom && y1 < h && !ink_in(cov, w, h, x0, y1, x1, y1 + 1);
        if (bottom) ++y1;
    }
    return {x0, y0, x1 - x0, y1 - y0, b.area};
}

} // namespace

PanelsFound find_panels(const std::vector<float>& coverage, int width, int height, const PanelSearch& opt) {
    PanelsFound found;
    const std::vector<Box> all = components(coverage, width, height);
    double largest = 0;
    for (const Box& b : all) largest = std::max(largest, b.area);
    std::vector<Box> drawings;
    for (const Box& b : all) {
        if (b.area >= opt.mark_fraction * largest) drawings.push_back(b);
        else ++found.marks;
    }
    if (drawings.empty()) return found;
    const int gap = std::max(3, int(std::lround(opt.gap_fraction * std::max(width, height))));
    std::vector<Box> groups, panels;
    xy_cut(drawings, gap, groups);
    // A group of pieces none of which is a drawing's size is text (a title, a letter of a
    // title written vertically, a dimension's number): its pieces are marks.
    for (const Box& g : groups) {
        double big = 0;
        int pieces = 0;
        for (const Box& b : drawings)
            if (b.x0 >= g.x0 && b.x1 <= g.x1 && b.y0 >= g.y0 && b.y1 <= g.y1) {
                big = std::max(big, b.area);
                ++pieces;
            }
        if (big < opt.text_fraction * largest) found.marks += pieces;
        else panels.push_back(g);
    }
    reading_order(panels);
    for (const Box& b : panels) {
        const int margin =
            std::clamp(int(std::lround(opt.margin_fraction * std::max(b.x1 - b.x0, b.y1 - b.y0))), 6, 64);
        found.panels.push_back(grow(coverage, width, height, b, margin));
    }
    return found;
}

namespace {

// The pixels of a frame drawn around the whole sheet, from the sheet's coverage (object
// where the frame encloses it): the piece of object spanning at least 80 % of the sheet
// both ways, and within it the ink (colour distance to the paper over `threshold`) joined
// to its outer edge. Empty when there is no such piece, or when that ink covers more than
// a quarter of its box (a drawing filling the sheet, not a frame).
std::vector<char> frame_pixels(const Image& img, const std::vector<float>& cov, double threshold) {
    const int w = img.width, h = img.height;
    const std::size_t n = std::size_t(w) * h;
    std::array<double, 3> paper{0, 0, 0};
    std::size_t np = 0;
    for (std::size_t i = 0; i < n; ++i)
        if (cov[i] == 0.0f) {
            const auto p = img.rgba(i);
            for (int k = 0; k < 3; ++k) paper[std::size_t(k)] += p[std::size_t(k)];
            ++np;
        }
    if (np == 0) return {};
    for (double& c : paper) c /= double(np);
    auto ink = [&](std::size_t i) {
        const auto p = img.rgba(i);
        double d = 0;
        for (int k = 0; k < 3; ++k)
            d += (p[std::size_t(k)] - paper[std::size_t(k)]) * (p[std::size_t(k)] - paper[std::size_t(k)]);
        return cov[i] >= 0.5f && std::sqrt(d / 3.0) >= threshold;
    };
    std::vector<char> frame(n, 0);
    std::vector<std::size_t> stack;
    // Seeds: object pixels beside paper the border reaches (every piece's outer edge).
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            const bool edge = x == 0 || y == 0 || x + 1 == w || y + 1 == h || cov[i - 1] == 0.0f ||
                              cov[i + 1] == 0.0f || cov[i - std::size_t(w)] == 0.0f || cov[i + std::size_t(w)] == 0.0f;
            if (edge && ink(i)) stack.push_back(i);
        }
    std::vector<int> seen(n, -1);
    int best = -1;
    std::size_t best_area = 0;
    for (std::size_t s : stack) {
        if (seen[s] >= 0) continue;
        const int id = int(s);
        std::vector<std::size_t> todo{s}, piece;
        seen[s] = id;
        int x0 = w, y0 = h, x1 = 0, y1 = 0;
        while (!todo.empty()) {
            const std::size_t i = todo.back();
            todo.pop_back();
            piece.push_back(i);
            const int x = int(i % std::size_t(w)), y = int(i / std::size_t(w));
            x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x + 1), y1 = std::max(y1, y + 1);
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
                    const std::size_t j = std::size_t(yy) * w + xx;
                    if (seen[j] < 0 && ink(j)) {
                        seen[j] = id;
                        todo.push_back(j);
                    }
                }
        }
        const double box = double(x1 - x0) * double(y1 - y0);
        if (x1 - x0 >= 0.8 * w && y1 - y0 >= 0.8 * h && double(piece.size()) <= 0.25 * box &&
            piece.size() > best_area) {
            best = id;
            best_area = piece.size();
        }
    }
    if (best < 0) return {};
    for (std::size_t i = 0; i < n; ++i) frame[i] = seen[i] == best;
    return frame;
}

// `img` with the `frame` pixels and their anti-aliased fringe (two pixels around) painted
// in the paper's colour: the mean of the paper beside the frame.
Image erase_frame(const Image& img, const std::vector<char>& frame) {
    const int w = img.width, h = img.height, r = 2;
    std::vector<char> grown(frame.size(), 0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            if (frame[std::size_t(y) * w + x])
                for (int yy = std::max(0, y - r); yy <= std::min(h - 1, y + r); ++yy)
                    for (int xx = std::max(0, x - r); xx <= std::min(w - 1, x + r); ++xx)
                        grown[std::size_t(yy) * w + xx] = 1;
    // The paper: pixels one step beyond the grown frame.
    std::array<double, 4> paper{0, 0, 0, 0};
    std::size_t np = 0;
    for (int y = 1; y + 1 < h; ++y)
        for (int x = 1; x + 1 < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            if (grown[i] || !(grown[i - 1] || grown[i + 1] || grown[i - std::size_t(w)] || grown[i + std::size_t(w)]))
                continue;
            const auto p = img.rgba(i);
            for (int k = 0; k < 4; ++k) paper[std::size_t(k)] += p[std::size_t(k)];
            ++np;
        }
    Image out = img;
    if (np == 0) return out;
    for (double& c : paper) c /= double(np);
    for (std::size_t i = 0; i < grown.size(); ++i) {
        if (!grown[i]) continue;
        for (int k = 0; k < out.channels; ++k) {
            const double v = out.channels < 3 ? paper[0] : paper[std::size_t(k)];
            const std::size_t s = i * std::size_t(out.channels) + std::size_t(k);
            if (out.eight_bit()) out.bytes[s] = std::uint8_t(std::lround(std::clamp(v, 0.0, 1.0) * 255.0));
            else out.pixels[s] = float(v);
        }
    }
    return out;
}

} // namespace

std::vector<float> sheet_coverage(const Image& img, const ImageInfo& info, const SilhouetteOptions& so, int& frames) {
    SilhouetteResult res = extract_silhouette(img, info, so);
    std::vector<float> cov = res.coverage.full();
    frames = 0;
    // Frames inside frames: each erased in turn (at most three).
    Image erased;
    for (const Image* at = &img; frames < 3;) {
        const std::vector<char> frame = frame_pixels(*at, cov, res.threshold);
        if (frame.empty()) break;
        erased = erase_frame(*at, frame);
        at = &erased;
        res = extract_silhouette(erased, info, so);
        cov = res.coverage.full();
        ++frames;
    }
    return cov;
}

Image crop_image(const Image& sheet, const SheetPanel& p) {
    Image out;
    out.width = p.width;
    out.height = p.height;
    out.channels = sheet.channels;
    // The panel's samples as the sheet holds them (bytes or floats).
    auto crop = [&](const auto& from, auto& to) {
        to.resize(std::size_t(p.width) * p.height * sheet.channels);
        for (int y = 0; y < p.height; ++y)
            std::copy_n(from.begin() + long((std::size_t(y + p.y0) * sheet.width + p.x0) * sheet.channels),
                        std::size_t(p.width) * sheet.channels,
                        to.begin() + long(std::size_t(y) * p.width * sheet.channels));
    };
    if (sheet.eight_bit()) crop(sheet.bytes, out.bytes);
    else crop(sheet.pixels, out.pixels);
    return out;
}

SheetViews split_sheets(const Manifest& m, const PanelSearch& opt) {
    SheetViews out;
    out.images.resize(m.views.size());
    out.infos.resize(m.views.size());
    out.panels.resize(m.views.size());
    for (const ManifestSheet& sh : m.sheets) {
        const fs::path rel = sh.image.lexically_relative(m.file.parent_path());
        const std::string where = m.file.string() + ":" + std::to_string(sh.line) + ": sheet \"" +
                                  (rel.empty() ? sh.image : rel).generic_string() + "\"";
        const ManifestView& first = m.views.at(sh.views.at(0));
        ImageInfo info;
        Image img;
        PanelsFound found;
        int frames = 0;
        try {
            img = read_image(sh.image, &info, true, opt.svg_size);
            SilhouetteOptions so; // the sheet's options; every mark kept, so panels are whole
            so.background = first.background;
            so.threshold = first.threshold.value_or(-1.0);
            so.keep = "all";
            so.holes = "fill";
            // Panels are found from the ink as drawn; each panel's own extraction then closes
            // its gaps and drops its shadow (the line-art steps run on the whole sheet made
            // the test sheets fall into twice their panels).
            so.shadow = "keep";
            so.close_gaps = 0;
            found = find_panels(sheet_coverage(img, info, so, frames), img.width, img.height, opt);
        } catch (const Error& e) {
            throw Error(where + ": " + e.what());
        }
        std::string names, placed;
        for (std::size_t k = 0; k < sh.views.size(); ++k) names += (k ? ", " : "") + m.views[sh.views[k]].key;
        if (found.panels.size() != sh.views.size())
            throw Error(where + " holds " + std::to_string(found.panels.size()) + " panel" +
                        (found.panels.size() == 1 ? "" : "s") + " but names " + std::to_string(sh.views.size()) +
                        " view" + (sh.views.size() == 1 ? "" : "s") + " (" + names + ")");
        for (std::size_t k = 0; k < sh.views.size(); ++k) {
            const std::size_t i = sh.views[k];
            const SheetPanel& p = found.panels[k];
            out.images[i] = crop_image(img, p);
            out.infos[i] = info;
            out.panels[i] = p;
            placed += std::string(k ? ", " : "") + "\"" + m.views[i].key + "\" at (" + std::to_string(p.x0) + ", " +
                      std::to_string(p.y0) + ") " + std::to_string(p.width) + "x" + std::to_string(p.height);
        }
        out.notes.push_back(where.substr(where.find("sheet \"")) + ": " + std::to_string(found.panels.size()) +
                            " panels: " + placed + "; " + std::to_string(found.marks) +
                            " mark(s) outside them left out (labels, specks)" +
                            (frames ? "; " + std::to_string(frames) + " frame(s) around the sheet left out" : ""));
    }
    return out;
}

} // namespace cm
