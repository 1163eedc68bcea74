// score_drawings DRAWINGS/views.yaml RENDERS/views.yaml: scores each drawing as an artist
// judges a model, by laying the model over it. RENDERS holds the model rendered from the same
// views (render-views, any framing); each render's silhouette is fitted to the drawing's by
// a similarity (scale, turn, shift) that minimises their disagreement, then the drawing's
// share not covered (missing) and the share covered beyond it (extra) are printed, one line
// per view: "<view> <missing %> <extra %>". Silhouettes are extracted as views.load does,
// without reconciliation. With OUT_DIR, writes OUT_DIR/<view>-overlay.png: grey where both
// agree, orange where the drawing is not covered (missing), blue where the model covers
// beyond it (extra).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "core/error.h"
#include "io/image_io.h"
#include "load.h"

using namespace cm;

namespace {

struct Mask {
    int w = 0, h = 0;
    std::vector<char> in;
    double cx = 0, cy = 0, area = 0;
    bool at(int x, int y) const { return x >= 0 && y >= 0 && x < w && y < h && in[std::size_t(y) * w + x]; }
};

Mask mask_of(const View& v) {
    Mask m;
    m.w = v.width, m.h = v.height;
    m.in.resize(std::size_t(m.w) * m.h);
    for (int y = 0; y < m.h; ++y)
        for (int x = 0; x < m.w; ++x)
            if ((m.in[std::size_t(y) * m.w + x] = v.inside(x, y))) m.cx += x + 0.5, m.cy += y + 0.5, ++m.area;
    m.cx /= m.area, m.cy /= m.area;
    return m;
}

// Drawing pixel q to render pixel: p = cM + R(-a) (q - cD - t) / s.
struct Sim {
    double s = 1, a = 0, tx = 0, ty = 0;
};

// Missing and extra pixel counts of the render laid over the drawing by `f`, every
// `stride`-th pixel of the drawing; with `overlay`, each pixel's colour there.
std::pair<double, double> disagreement(const Mask& d, const Mask& r, const Sim& f, int stride,
                                       Image* overlay = nullptr) {
    const double cs = std::cos(f.a), sn = std::sin(f.a);
    double missing = 0, extra = 0;
    for (int y = 0; y < d.h; y += stride)
        for (int x = 0; x < d.w; x += stride) {
            const double qx = x + 0.5 - d.cx - f.tx, qy = y + 0.5 - d.cy - f.ty;
            const double px = r.cx + (cs * qx + sn * qy) / f.s, py = r.cy + (-sn * qx + cs * qy) / f.s;
            const bool inr = r.at(int(std::floor(px)), int(std::floor(py)));
            const bool ind = d.in[std::size_t(y) * d.w + x];
            missing += ind && !inr;
            extra += inr && !ind;
            if (overlay) {
                const std::array<float, 3> c = ind && inr ? std::array<float, 3>{0.6f, 0.6f, 0.6f}
                                               : ind      ? std::array<float, 3>{1.0f, 0.45f, 0.0f}
                                               : inr      ? std::array<float, 3>{0.2f, 0.45f, 1.0f}
                                                          : std::array<float, 3>{1.0f, 1.0f, 1.0f};
                for (int k = 0; k < 3; ++k)
                    overlay->pixels[(std::size_t(y) * d.w + x) * 4 + std::size_t(k)] = c[std::size_t(k)];
                overlay->pixels[(std::size_t(y) * d.w + x) * 4 + 3] = 1.0f;
            }
        }
    return {missing * stride * stride, extra * stride * stride};
}

Sim fit(const Mask& d, const Mask& r) {
    Sim f;
    f.s = std::sqrt(d.area / r.area);
    auto cost = [&](const Sim& g, int stride) {
        const auto [m, e] = disagreement(d, r, g, stride);
        return m + e;
    };
    std::array<double, 4> step{0.02, 0.02, 8.0, 8.0};
    for (int stride : {4, 2, 1}) {
        double best = cost(f, stride);
        for (int round = 0; round < 40; ++round) {
            bool better = false;
            for (int k = 0; k < 4; ++k)
                for (double sign : {1.0, -1.0}) {
                    Sim g = f;
                    double* p[4] = {&g.s, &g.a, &g.tx, &g.ty};
                    *p[k] += sign * step[std::size_t(k)] * (k == 0 ? f.s : 1.0);
                    if (const double c = cost(g, stride); c < best) best = c, f = g, better = true;
                }
            if (!better) {
                for (auto& s : step) s *= 0.5;
                if (step[2] < 0.2 * stride) break;
            }
        }
        step = {0.005, 0.005, 1.0, 1.0};
    }
    return f;
}

} // namespace

int main(int argc, char** argv) {
    if (argc != 3 && argc != 4) {
        std::fprintf(stderr, "usage: score_drawings DRAWINGS/views.yaml RENDERS/views.yaml [OUT_DIR]\n");
        return 2;
    }
    try {
        LoadViewsOptions opt;
        opt.reconcile = "off";
        const Views drawings = load_views(argv[1], opt).value, renders = load_views(argv[2], opt).value;
        for (const View& dv : drawings.views) {
            const View* rv = nullptr;
            for (const View& v : renders.views)
                if (v.name == dv.name) rv = &v;
            if (!rv) throw Error("no render of view \"" + dv.name + "\" in " + std::string(argv[2]));
            const Mask d = mask_of(dv), r = mask_of(*rv);
            Image overlay{d.w, d.h, 4, std::vector<float>(std::size_t(d.w) * d.h * 4, 0.0f), {}};
            const auto [missing, extra] = disagreement(d, r, fit(d, r), 1, argc == 4 ? &overlay : nullptr);
            if (argc == 4) write_image(overlay, std::filesystem::path(argv[3]) / (dv.name + "-overlay.png"));
            std::printf("%s %.3f %.3f\n", dv.name.c_str(), 100.0 * missing / d.area, 100.0 * extra / d.area);
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "score_drawings: %s\n", e.what());
        return 1;
    }
    return 0;
}
