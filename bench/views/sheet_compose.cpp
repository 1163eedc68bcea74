// sheet_compose OUT.png DRAWING.png...: a turnaround sheet from separate drawings (side by
// side with blank gaps, a text-like label under each), as docs/results/sheet.md uses.
// sheet_compose --panels OUT.png SHEET.png: the sheet with the crop of every panel
// views.load finds outlined, in reading order from red to blue (docs/views.md).
#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "io/image_io.h"
#include "sheet.h"
#include "silhouette.h"
#include "support/shapes.h"

namespace {

void outline_panels(const char* out, const char* sheet) {
    cm::ImageInfo info;
    cm::Image img = cm::read_image(sheet, &info);
    cm::SilhouetteOptions so;
    so.keep = "all";
    so.holes = "fill";
    const auto found = cm::find_panels(cm::extract_silhouette(img, info, so).coverage.full(), img.width, img.height);
    for (std::size_t k = 0; k < found.panels.size(); ++k) {
        const cm::SheetPanel& p = found.panels[k];
        const float t = found.panels.size() > 1 ? float(k) / float(found.panels.size() - 1) : 0.0f;
        const float rgb[3] = {1.0f - t, 0.3f, t};
        auto put = [&](int x, int y) {
            for (int c = 0; c < 3; ++c) img.at(x, y, c) = rgb[c];
        };
        for (int w = 0; w < 2; ++w) {
            for (int x = p.x0; x < p.x0 + p.width; ++x) put(x, p.y0 + w), put(x, p.y0 + p.height - 1 - w);
            for (int y = p.y0; y < p.y0 + p.height; ++y) put(p.x0 + w, y), put(p.x0 + p.width - 1 - w, y);
        }
        std::printf("panel %zu: (%d, %d) %dx%d\n", k + 1, p.x0, p.y0, p.width, p.height);
    }
    std::printf("%d mark(s) left out\n", found.marks);
    cm::write_image(img, out);
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 3 || (std::string(argv[1]) == "--panels" && argc != 4)) {
        std::fprintf(stderr,
                     "usage: sheet_compose OUT.png DRAWING.png...\n       sheet_compose --panels OUT.png SHEET.png\n");
        return 2;
    }
    try {
        if (std::string(argv[1]) == "--panels") {
            outline_panels(argv[2], argv[3]);
            return 0;
        }
        std::vector<cm::Image> drawings;
        for (int i = 2; i < argc; ++i) drawings.push_back(cm::read_image(argv[i]));
        const int gap = std::max(8, drawings.front().width / 16);
        cm::write_image(cm::test::compose_sheet(drawings, gap, gap), argv[1]);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sheet_compose: %s\n", e.what());
        return 1;
    }
    return 0;
}
