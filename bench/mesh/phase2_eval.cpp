// phase2_eval MC_MESH MANIFEST [ANGLES]: the phase-2 figures of docs/results/phase2.md for
// one model. From the Marching Cubes mesh of the views in MANIFEST:
//  - smoothing, 10 iterations: Laplacian, Taubin, and both with the hull constraint
//    (0.5 px): volume change against the Marching Cubes mesh, xor_pct, seconds;
//  - from the hull-constrained Laplacian mesh (the paper pipeline's smoothing), the
//    reduction sweep over max_angle_deg (default 5,10,...,40): faces, share of the
//    Marching Cubes faces, xor_pct, closed/manifold, self-intersections, seconds; and
//    quadric decimation to the same face counts, with the same figures.
// Prints one JSON object.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "core/mesh.h"
#include "geometry/hull_distance.h"
#include "geometry/mesh_check.h"
#include "geometry/mesh_intersect.h"
#include "io/mesh_io.h"
#include "load.h"
#include "mesh_decimate.h"
#include "mesh_smooth.h"
#include "metrics/silhouette_error.h"
#include "render/raster.h"

using namespace cm;
using json = nlohmann::json;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

json describe(const Mesh& m, const Views& views, std::size_t mc_faces, double secs) {
    const MeshCheck c = check_mesh(m);
    return {{"faces", m.face_count()},
            {"face_pct_of_mc", 100.0 * double(m.face_count()) / double(mc_faces)},
            {"xor_pct", silhouette_error(m, views).xor_pct},
            {"closed_manifold", c.closed_manifold() && c.degenerate_faces == 0},
            {"outward", c.signed_volume > 0},
            {"self_intersections", count_self_intersections(m)},
            {"volume", c.signed_volume},
            {"seconds", secs}};
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::cerr << "usage: phase2_eval MC_MESH MANIFEST [ANGLES]\n";
        return 2;
    }
    try {
        std::vector<double> angles = {5, 10, 15, 20, 25, 30, 35, 40};
        if (argc > 3) {
            angles.clear();
            std::stringstream ss(argv[3]);
            for (std::string a; std::getline(ss, a, ',');) angles.push_back(std::stod(a));
        }
        const Views views = load_views(argv[2], LoadViewsOptions{}).value;
        const Mesh mc = read_mesh(argv[1]);
        const std::size_t mc_faces = mc.face_count();
        const double v0 = check_mesh(mc).signed_volume;
        json out;
        out["mc"] = describe(mc, views, mc_faces, 0);
        const HullDistance hull(views);

        json smooth = json::object();
        Mesh paper_smooth;
        for (const char* variant : {"laplacian", "taubin", "laplacian_hull", "taubin_hull"}) {
            const std::string v = variant;
            Mesh m = mc;
            SmoothOptions o;
            o.iterations = 10;
            o.method = v.rfind("taubin", 0) == 0 ? SmoothOptions::Method::Taubin : SmoothOptions::Method::Laplacian;
            if (v.find("hull") != std::string::npos) {
                o.constrain = SmoothOptions::Constrain::Hull;
                o.tolerance_px = 0.5;
            }
            const auto t0 = std::chrono::steady_clock::now();
            smooth_mesh_in_place(m, o, &hull);
            const double secs = seconds_since(t0);
            const double v1 = check_mesh(m).signed_volume;
            smooth[v] = {{"volume_change_pct", 100.0 * (v1 - v0) / v0},
                         {"xor_pct", silhouette_error(m, views).xor_pct},
                         {"seconds", secs}};
            if (v == "laplacian_hull") paper_smooth = m;
        }
        out["smooth"] = smooth;

        json sweep = json::array();
        for (double a : angles) {
            Mesh r = paper_smooth;
            ReduceOptions ro;
            ro.max_angle_deg = a;
            auto t0 = std::chrono::steady_clock::now();
            reduce_mesh_in_place(r, ro);
            const json jr = describe(r, views, mc_faces, seconds_since(t0));
            Mesh q = paper_smooth;
            QuadricOptions qo;
            qo.target_faces = r.face_count();
            t0 = std::chrono::steady_clock::now();
            quadric_decimate_in_place(q, qo);
            const json jq = describe(q, views, mc_faces, seconds_since(t0));
            sweep.push_back({{"max_angle_deg", a}, {"reduce", jr}, {"quadric", jq}});
            std::cerr << "  angle " << a << ": " << jr["faces"] << " faces, xor " << jr["xor_pct"] << " % (quadric "
                      << jq["xor_pct"] << " %)\n";
        }
        out["sweep"] = sweep;
        std::cout << out.dump(1) << "\n";
    } catch (const std::exception& e) {
        std::cerr << "phase2_eval: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
