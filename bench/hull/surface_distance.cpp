// surface_distance RECON TRUTH [--up +Y] [--front +Z] [--samples N]
// The 3D error of a reconstruction against the true model (cm::surface_distance: mean
// two-sided surface distance, % of the true model's bounding-box diagonal). The true
// model is turned from its own axes (--up, --front) into the output frame (Y up, front
// +Z) and moved so its box's bottom centre is at the origin, as `conceptmesh
// render-views` frames it, so a mesh reconstructed from those views lies on it. The one
// implementation of the figure: bench/hull/run_plausible.sh and bench/reproduce call it.
// Prints one JSON line.
#include <cctype>
#include <cstdio>
#include <iostream>
#include <string>

#include "core/mesh.h"
#include "geometry/surface_distance.h"
#include "io/mesh_io.h"

namespace {

cm::Vec3d axis_of(const std::string& s) {
    if (s.empty() || s.size() > 2 || (s.size() == 2 && s[0] != '+' && s[0] != '-'))
        throw std::runtime_error("bad axis " + s);
    const double sign = s[0] == '-' ? -1 : 1;
    const char c = char(std::toupper(static_cast<unsigned char>(s.back())));
    if (c == 'X') return {sign, 0, 0};
    if (c == 'Y') return {0, sign, 0};
    if (c == 'Z') return {0, 0, sign};
    throw std::runtime_error("bad axis " + s);
}

} // namespace

int main(int argc, char** argv) {
    try {
        std::string recon, truth, up = "+Y", front = "+Z";
        int samples = 100000;
        for (int i = 1; i < argc; ++i) {
            const std::string a = argv[i];
            if (a == "--up" && i + 1 < argc) up = argv[++i];
            else if (a == "--front" && i + 1 < argc) front = argv[++i];
            else if (a == "--samples" && i + 1 < argc) samples = std::stoi(argv[++i]);
            else if (recon.empty()) recon = a;
            else if (truth.empty()) truth = a;
            else throw std::runtime_error("unexpected argument " + a);
        }
        if (truth.empty() || samples < 1) {
            std::cerr << "usage: surface_distance RECON TRUTH [--up +Y] [--front +Z] [--samples N]\n";
            return 2;
        }
        const cm::Mesh r = cm::read_mesh(recon);
        cm::Mesh t = cm::read_mesh(truth);
        const cm::Vec3d U = axis_of(up), F = axis_of(front), X = cm::cross(U, F);
        if (cm::length(X) < 0.5) throw std::runtime_error("--up and --front are the same axis");
        for (auto& p : t.positions) {
            const cm::Vec3d q(p);
            p = cm::Vec3f(cm::Vec3d{cm::dot(q, X), cm::dot(q, U), cm::dot(q, F)});
        }
        cm::Vec3f lo, hi;
        t.bounds(lo, hi);
        const cm::Vec3f pivot{0.5f * (lo.x + hi.x), lo.y, 0.5f * (lo.z + hi.z)};
        for (auto& p : t.positions) p = p - pivot;
        const cm::SurfaceDistance d = cm::surface_distance(r, t, samples);
        std::printf(
            "{\"mean_pct\": %.4f, \"recon_to_true_pct\": %.4f, \"true_to_recon_pct\": %.4f, \"diag\": %.6g, "
            "\"beyond_reach\": %zu}\n",
            d.mean_pct, 100.0 * d.recon_to_true / d.diag, 100.0 * d.true_to_recon / d.diag, d.diag, d.beyond_reach);
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "surface_distance: " << e.what() << "\n";
        return 1;
    }
}
