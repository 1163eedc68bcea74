// surface_distance RECON TRUTH [--up +Y] [--front +Z] [--samples N]
// The 3D error of a reconstruction against the true model: the mean two-sided surface
// distance, as a percentage of the true model's bounding-box diagonal. The true model is
// turned from its own axes into the output frame (Y up, front +Z) and moved so its box's
// bottom centre is at the origin, as `conceptmesh render-views` frames it, so a mesh
// reconstructed from those views lies on it. Each mesh is sampled at N points (area
// weighted, fixed seed) and each point's distance to the other mesh is read from that
// mesh's unsigned distance field (OpenVDB, exact within a narrow band of 12 voxels of diag/256).
// Prints one JSON line.
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/MeshToVolume.h>

#include <cstdio>
#include <iostream>
#include <random>
#include <string>

#include "core/mesh.h"
#include "io/mesh_io.h"

namespace {

cm::Vec3d axis_of(const std::string& s) {
    if (s.size() < 1 || s.size() > 2) throw std::runtime_error("bad axis " + s);
    const double sign = s[0] == '-' ? -1 : 1;
    const char c = char(std::toupper(s.back()));
    if (c == 'X') return {sign, 0, 0};
    if (c == 'Y') return {0, sign, 0};
    if (c == 'Z') return {0, 0, sign};
    throw std::runtime_error("bad axis " + s);
}

struct Field {
    openvdb::FloatGrid::Ptr grid;
    float band = 0;
};

Field distance_field(const cm::Mesh& m, double voxel, int band_voxels) {
    std::vector<openvdb::Vec3s> pts;
    std::vector<openvdb::Vec3I> tris;
    std::vector<openvdb::Vec4I> quads;
    auto xf = openvdb::math::Transform::createLinearTransform(voxel);
    for (const auto& p : m.positions) pts.push_back(xf->worldToIndex(openvdb::Vec3d(p.x, p.y, p.z)));
    for (const auto& t : m.triangles) tris.emplace_back(t[0], t[1], t[2]);
    Field f;
    f.grid = openvdb::tools::meshToUnsignedDistanceField<openvdb::FloatGrid>(*xf, pts, tris, quads, float(band_voxels));
    f.band = float(band_voxels * voxel);
    return f;
}

// Mean distance from `n` area-weighted samples of `a` to the surface of field `fb`.
double mean_distance(const cm::Mesh& a, const Field& fb, int n, std::size_t& beyond) {
    std::vector<double> cum;
    double area = 0;
    for (const auto& t : a.triangles) {
        const cm::Vec3d p(a.positions[t[0]]), q(a.positions[t[1]]), r(a.positions[t[2]]);
        area += 0.5 * cm::length(cm::cross(q - p, r - p));
        cum.push_back(area);
    }
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0, 1);
    auto acc = fb.grid->getConstAccessor();
    const auto& xf = fb.grid->transform();
    double sum = 0;
    for (int i = 0; i < n; ++i) {
        const std::size_t k = std::size_t(std::lower_bound(cum.begin(), cum.end(), u(rng) * area) - cum.begin());
        const auto& t = a.triangles[std::min(k, a.triangles.size() - 1)];
        double s = u(rng), w = u(rng);
        if (s + w > 1) s = 1 - s, w = 1 - w;
        const cm::Vec3d p(a.positions[t[0]]), q(a.positions[t[1]]), r(a.positions[t[2]]);
        const cm::Vec3d x = p + (q - p) * s + (r - p) * w;
        const float d = openvdb::tools::BoxSampler::sample(acc, xf.worldToIndex(openvdb::Vec3d(x.x, x.y, x.z)));
        if (d >= fb.band * 0.999f) ++beyond;
        sum += d;
    }
    return sum / n;
}

} // namespace

int main(int argc, char** argv) {
    try {
        openvdb::initialize();
        std::string recon, truth, up = "+Y", front = "+Z";
        int samples = 100000;
        for (int i = 1; i < argc; ++i) {
            const std::string a = argv[i];
            if (a == "--up" && i + 1 < argc) up = argv[++i];
            else if (a == "--front" && i + 1 < argc) front = argv[++i];
            else if (a == "--samples" && i + 1 < argc) samples = std::stoi(argv[++i]);
            else if (recon.empty()) recon = a;
            else truth = a;
        }
        if (truth.empty()) {
            std::cerr << "usage: surface_distance RECON TRUTH [--up +Y] [--front +Z] [--samples N]\n";
            return 2;
        }
        const cm::Mesh r = cm::read_mesh(recon);
        cm::Mesh t = cm::read_mesh(truth);
        const cm::Vec3d U = axis_of(up), F = axis_of(front), X = cm::cross(U, F);
        for (auto& p : t.positions) {
            const cm::Vec3d q(p);
            p = cm::Vec3f(cm::Vec3d{cm::dot(q, X), cm::dot(q, U), cm::dot(q, F)});
        }
        cm::Vec3f lo, hi;
        t.bounds(lo, hi);
        const cm::Vec3f pivot{0.5f * (lo.x + hi.x), lo.y, 0.5f * (lo.z + hi.z)};
        for (auto& p : t.positions) p = p - pivot;
        const double diag = cm::length(cm::Vec3d(hi - lo));
        const double voxel = diag / 256.0;
        const int band = 12; // 4.7 % of the diagonal
        std::size_t beyond = 0;
        const double rt = mean_distance(r, distance_field(t, voxel, band), samples, beyond);
        const double tr = mean_distance(t, distance_field(r, voxel, band), samples, beyond);
        std::printf(
            "{\"mean_pct\": %.4f, \"recon_to_true_pct\": %.4f, \"true_to_recon_pct\": %.4f, \"diag\": %.6g, "
            "\"beyond_band\": %zu}\n",
            100.0 * 0.5 * (rt + tr) / diag, 100.0 * rt / diag, 100.0 * tr / diag, diag, beyond);
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "surface_distance: " << e.what() << "\n";
        return 1;
    }
}
