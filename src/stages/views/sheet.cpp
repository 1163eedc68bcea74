#include "sheet.h"

#include <algorithm>
#include <cmath>

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
    std::vector<Box> panels;
    xy_cut(drawings, gap, panels);
    reading_order(panels);
    for (const Box& b : panels) {
        const int margin =
            std::clamp(int(std::lround(opt.margin_fraction * std::max(b.x1 - b.x0, b.y1 - b.y0))), 6, 64);
        found.panels.push_back(grow(coverage, width, height, b, margin));
    }
    return found;
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
        try {
            img = read_image(sh.image, &info, true);
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
            found = find_panels(extract_silhouette(img, info, so).coverage.full(), img.width, img.height, opt);
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
                            " mark(s) outside them left out (labels, specks)");
    }
    return out;
}

} // namespace cm
