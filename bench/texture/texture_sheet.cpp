// texture_sheet MESH VIEWS.yaml OUT.png [PANEL] [--turntable OUT34.png]: the contact sheet of a
// coloured mesh against the drawings it was coloured from. One row per view of a manifest
// with fixed cameras (scale and origin, as render-views and flat_art write them): the
// drawing, the mesh's colour seen through the same camera (unlit), and the CIE76 delta E
// per pixel (black 0, white 20 and over) inside the silhouette, the drawing's ink strokes
// left grey as the outside is (they have no fill colour to hold the mesh to). The last row shows the
// model lit from a three-quarter view (azimuth 35, elevation 25). With --turntable the
// three-quarter picture is also written on its own; VIEWS "-" gives that picture alone.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "core/error.h"
#include "drawing/ink.h"
#include "io/image_io.h"
#include "io/manifest.h"
#include "io/mesh_io.h"
#include "render/colour.h"
#include "render/raster.h"
#include "render/textured.h"

namespace fs = std::filesystem;
using namespace cm;

namespace {

// Nearest-neighbour resize of an RGB(A) image into a panel of `p` x `p` (aspect kept, centred on white).
void blit(Image& sheet, const Image& src, int ox, int oy, int p) {
    const double s = double(p) / std::max(src.width, src.height);
    const int w = int(src.width * s), h = int(src.height * s);
    const int x0 = ox + (p - w) / 2, y0 = oy + (p - h) / 2;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const int sx = std::min(src.width - 1, int(x / s)), sy = std::min(src.height - 1, int(y / s));
            for (int k = 0; k < 3; ++k) sheet.at(x0 + x, y0 + y, k) = src.at(sx, sy, std::min(k, src.channels - 1));
        }
}

Image lit_three_quarter(const Mesh& m, int size) {
    Vec3f lo, hi;
    m.bounds(lo, hi);
    const Camera cam = framed_camera(Camera::from_azimuth_elevation(35, 25), Vec3d(lo), Vec3d(hi), size, size);
    Image img = render_colour(m, cam, size, size, {1, 1, 1});
    const DepthImage d = render_depth(m, cam, size, size);
    const Vec3d light = normalize(Vec3d(0.4, 0.8, 0.6));
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            if (!d.covered(x, y)) continue;
            const auto& t = m.triangles[d.face[std::size_t(y) * size + x]];
            const Vec3d a(m.positions[t[0]]), b(m.positions[t[1]]), c(m.positions[t[2]]);
            const Vec3d n = normalize(cross(b - a, c - a));
            const float shade = float(0.45 + 0.55 * std::max(0.0, dot(n, light)));
            for (int k = 0; k < 3; ++k) img.at(x, y, k) = linear_to_srgb(srgb_to_linear(img.at(x, y, k)) * shade);
        }
    return img;
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 4) {
        std::fprintf(stderr, "usage: texture_sheet MESH VIEWS.yaml OUT.png [PANEL] [--turntable OUT34.png]\n");
        return 2;
    }
    try {
        const Mesh mesh = read_mesh(argv[1]);
        // "-" for VIEWS: no drawings to hold the mesh against, the three-quarter view alone.
        const Manifest man = std::string(argv[2]) == "-" ? Manifest{} : read_manifest(argv[2]);
        int panel = 320;
        std::string turntable;
        for (int i = 4; i < argc; ++i) {
            if (std::strcmp(argv[i], "--turntable") == 0 && i + 1 < argc) turntable = argv[++i];
            else panel = std::stoi(argv[i]);
        }
        const int rows = int(man.views.size()) + 1, gap = 8;
        Image sheet;
        sheet.width = 3 * panel + 4 * gap;
        sheet.height = rows * panel + (rows + 1) * gap;
        sheet.channels = 3;
        sheet.pixels.assign(std::size_t(sheet.width) * sheet.height * 3, 0.85f);
        int row = 0;
        for (const auto& mv : man.views) {
            if (!mv.view || !mv.scale || !mv.origin) throw Error("view \"" + mv.key + "\" has no fixed named camera");
            Camera cam = *Camera::named(*mv.view);
            cam.scale = *mv.scale;
            cam.cx = (*mv.origin)[0];
            cam.cy = (*mv.origin)[1];
            const Image drawing = read_image(mv.image);
            const Image rendered = render_colour(mesh, cam, drawing.width, drawing.height);
            std::vector<char> all(std::size_t(drawing.width) * drawing.height, 1);
            const std::vector<char> ink = find_ink(drawing, all, 4, 0.12f, false);
            Image de = rendered;
            for (int y = 0; y < de.height; ++y)
                for (int x = 0; x < de.width; ++x) {
                    float v = 1.0f;
                    if (rendered.at(x, y, 3) > 0.5f && !ink[std::size_t(y) * drawing.width + x]) {
                        const double e = delta_e76({rendered.at(x, y, 0), rendered.at(x, y, 1), rendered.at(x, y, 2)},
                                                   {drawing.at(x, y, 0), drawing.at(x, y, 1), drawing.at(x, y, 2)});
                        v = float(std::min(1.0, e / 20.0));
                        for (int k = 0; k < 3; ++k) de.at(x, y, k) = v;
                    } else {
                        for (int k = 0; k < 3; ++k) de.at(x, y, k) = 0.3f;
                    }
                }
            const int oy = gap + row * (panel + gap);
            blit(sheet, drawing, gap, oy, panel);
            blit(sheet, rendered, 2 * gap + panel, oy, panel);
            blit(sheet, de, 3 * gap + 2 * panel, oy, panel);
            ++row;
        }
        const Image three = lit_three_quarter(mesh, 2 * panel);
        blit(sheet, three, gap, gap + row * (panel + gap), panel);
        write_image(sheet, argv[3]);
        if (!turntable.empty()) write_image(lit_three_quarter(mesh, 1024), turntable);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "texture_sheet: %s\n", e.what());
        return 1;
    }
}
