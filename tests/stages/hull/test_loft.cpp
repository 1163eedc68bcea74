// hull.plausible's lofted prior (loft: 1) on shapes drawn in code whose answer is known:
// round shapes come back close to themselves, hard surfaces keep their flat faces, and every
// line of sight keeps its voxel; and the same shapes through pipelines/loft.yaml's own nodes.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <set>

#include "geometry/mesh_check.h"
#include "hull_steps.h"
#include "marching_cubes.h"
#include "plausible.h"
#include "support/shapes.h"
#include "support/stage_harness.h"
#include "support/test_support.h"

using namespace cm;
using namespace cm::test;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A shape known in closed form: its outline seen along each named view (signed, positive
// inside, in world units near the outline), its distance function (the same sign) and box.
struct Known {
    std::function<Outline(const Camera&)> outline;
    std::function<double(const Vec3d&)> sdf;
    Vec3d lo, hi;
};

std::shared_ptr<const Volume> lofted(const Known& k, int resolution, double share,
                                     std::shared_ptr<const Volume>* hull_out = nullptr) {
    std::vector<View> vs;
    for (const char* n : {"front", "right", "top"})
        vs.push_back(ortho_view(n, 320, 120.0, k.outline(*Camera::named(n))));
    auto views = make_views(std::move(vs), k.lo, k.hi);
    auto hull = carve_and_refine(views, resolution);
    PlausibleOptions opt;
    opt.loft = share;
    auto out = make_plausible(*hull, nullptr, opt).value;
    if (hull_out) *hull_out = hull;
    return out;
}

double diagonal(const Known& k) { return length(k.hi - k.lo); }

// Mean distance of the mesh's vertices to the known surface, in % of its box's diagonal
// (a signed distance's value near the surface, divided by its gradient's length).
double surface_error_pct(const Mesh& m, const Known& k) {
    double s = 0;
    const double h = 1e-4 * diagonal(k);
    for (const auto& p : m.positions) {
        const Vec3d q(p);
        Vec3d g;
        for (int a = 0; a < 3; ++a) {
            Vec3d e(0, 0, 0);
            e[a] = h;
            g[a] = (k.sdf(q + e) - k.sdf(q - e)) / (2 * h);
        }
        s += std::abs(k.sdf(q)) / std::max(length(g), 1e-9);
    }
    return 100.0 * s / double(m.positions.size()) / diagonal(k);
}

// The same distance over the mesh's area: each face's centroid and edge midpoints, weighted by
// the face's area (a reduced mesh keeps its vertices where the surface bends, so their mean
// is not the surface's).
double area_error_pct(const Mesh& m, const Known& k) {
    double s = 0, all = 0;
    const double h = 1e-4 * diagonal(k);
    auto dist = [&](const Vec3d& q) {
        Vec3d g;
        for (int a = 0; a < 3; ++a) {
            Vec3d e(0, 0, 0);
            e[a] = h;
            g[a] = (k.sdf(q + e) - k.sdf(q - e)) / (2 * h);
        }
        return std::abs(k.sdf(q)) / std::max(length(g), 1e-9);
    };
    for (const auto& t : m.triangles) {
        const Vec3d a(m.positions[t[0]]), b(m.positions[t[1]]), c(m.positions[t[2]]);
        const double area = 0.5 * length(cross(b - a, c - a));
        s += area * (dist((a + b + c) / 3.0) + dist((a + b) / 2.0) + dist((b + c) / 2.0) + dist((c + a) / 2.0)) / 4.0;
        all += area;
    }
    return 100.0 * s / std::max(all, 1e-30) / diagonal(k);
}

// Share of the mesh's area (%) whose face normal is within `deg` of the known surface's
// normal at the face's centre; with `part`, of the faces whose known normal it accepts only.
double area_within_pct(const Mesh& m, const Known& k, double deg,
                       const std::function<bool(const Vec3d&)>& part = nullptr) {
    double all = 0, good = 0;
    const double h = 1e-4 * diagonal(k);
    for (const auto& t : m.triangles) {
        const Vec3d a(m.positions[t[0]]), b(m.positions[t[1]]), c(m.positions[t[2]]);
        const Vec3d n = cross(b - a, c - a);
        const double area = 0.5 * length(n);
        if (area <= 0) continue;
        const Vec3d q = (a + b + c) / 3.0;
        Vec3d g;
        for (int ax = 0; ax < 3; ++ax) {
            Vec3d e(0, 0, 0);
            e[ax] = h;
            g[ax] = -(k.sdf(q + e) - k.sdf(q - e)); // outward
        }
        const double cosang = dot(n, g) / std::max(length(n) * length(g), 1e-30);
        if (part && !part(g / std::max(length(g), 1e-30))) continue;
        all += area;
        good += area * (std::acos(std::clamp(cosang, -1.0, 1.0)) * 180.0 / kPi <= deg);
    }
    return 100.0 * good / std::max(all, 1e-30);
}

// Axis-aligned ellipsoid of semi-axes r: the outline along a view axis is the ellipse of the
// other two semi-axes.
Known ellipsoid(Vec3d r) {
    auto f = [r](const Vec3d& q) {
        const double s = std::sqrt(std::pow(q[0] / r[0], 2) + std::pow(q[1] / r[1], 2) + std::pow(q[2] / r[2], 2));
        return (1.0 - s) * std::min({r[0], r[1], r[2]});
    };
    return {[f](const Camera&) { return Outline(f); }, f, -r, r};
}

// A standing (y axis) shape of revolution of radius rad(y) for y in [y0, y1]: the front and
// right views show the profile, the top the widest disc.
Known revolution(std::function<double(double)> rad, double y0, double y1, double rmax) {
    auto sdf = [rad, y0, y1](const Vec3d& q) {
        return std::min({rad(q[1]) - std::hypot(q[0], q[2]), q[1] - y0, y1 - q[1]});
    };
    auto out = [rad, y0, y1, rmax](const Camera& c) -> Outline {
        if (std::abs(c.d[1]) > 0.5) return [rmax](const Vec3d& q) { return rmax - std::hypot(q[0], q[2]); };
        return [rad, y0, y1](const Vec3d& q) {
            return std::min({rad(q[1]) - std::abs(q[0]) - std::abs(q[2]), q[1] - y0, y1 - q[1]});
        };
    };
    return {out, sdf, {-rmax, y0, -rmax}, {rmax, y1, rmax}};
}

Known box(Vec3d lo, Vec3d hi) {
    auto sdf = [lo, hi](const Vec3d& q) {
        double s = 1e300;
        for (int a = 0; a < 3; ++a) s = std::min({s, q[a] - lo[a], hi[a] - q[a]});
        return s;
    };
    return {[lo, hi](const Camera& c) { return box_outline(lo, hi, c.d); }, sdf, lo, hi};
}

// A wedge: the triangle x >= -1, y >= -1, x + y <= 0 (seen from the front) extruded along z.
Known wedge() {
    auto tri = [](const Vec3d& q) { return std::min({q[0] + 1.0, q[1] + 1.0, (0.0 - q[0] - q[1]) / std::sqrt(2.0)}); };
    const Vec3d lo(-1, -1, -0.8), hi(1, 1, 0.8);
    auto sdf = [tri, lo, hi](const Vec3d& q) { return std::min({tri(q), q[2] - lo[2], hi[2] - q[2]}); };
    auto out = [tri, lo, hi](const Camera& c) -> Outline {
        if (std::abs(c.d[2]) > 0.5) return tri;
        return box_outline(lo, hi, c.d);
    };
    return {out, sdf, lo, hi};
}

// A torus around the y axis (ring radius 0.25 about a circle of 0.75).
Known torus() {
    const double ring = 0.25, big = 0.75;
    auto out = [ring, big](const Camera& c) -> Outline {
        if (std::abs(c.d[1]) > 0.5)
            return [ring, big](const Vec3d& q) { return ring - std::abs(std::hypot(q[0], q[2]) - big); };
        return [ring, big](const Vec3d& q) {
            return ring - std::hypot(std::max(0.0, std::abs(q[0]) + std::abs(q[2]) - big), q[1]);
        };
    };
    auto sdf = [ring, big](const Vec3d& q) { return ring - std::hypot(std::hypot(q[0], q[2]) - big, q[1]); };
    return {out, sdf, {-1, -ring, -1}, {1, ring, 1}};
}

// The round shapes of the bar: a sphere, an ellipsoid, a cone, a vase (of revolution)
// and a torus.
std::vector<std::pair<const char*, Known>> round_shapes() {
    return {
        {"sphere", ellipsoid({1, 1, 1})},
        {"ellipsoid", ellipsoid({1.0, 0.6, 0.8})},
        {"cone", revolution([](double y) { return 0.5 * (1.0 - y); }, -1.0, 1.0, 1.0)},
        {"vase", revolution([](double y) { return 0.55 + 0.25 * std::sin(2.2 * y); }, -1.0, 1.0, 0.8)},
        {"torus", torus()},
    };
}

// The hard ones: a box, a standing cylinder and a wedge.
std::vector<std::pair<const char*, Known>> hard_shapes() {
    return {
        {"box", box({-1.0, -0.6, -0.8}, {1.0, 0.6, 0.8})},
        {"cylinder", revolution([](double) { return 0.7; }, -1.0, 1.0, 0.7)},
        {"wedge", wedge()},
    };
}

} // namespace

// Round shapes from front, right and top come back within 1 % of their diagonal (the
// visual hull of the sphere is at about 2 %), and the drawn views stay exact: every grid
// line along an axis that held a hull voxel still holds one.
TEST(HullLoft, RoundShapesComeBackWithinOnePercent) {
    for (const auto& [name, k] : round_shapes()) {
        std::shared_ptr<const Volume> hull;
        auto out = lofted(k, 96, 1.0, &hull);
        const Mesh mh = marching_cubes(*hull).value, ml = marching_cubes(*out).value;
        const double eh = surface_error_pct(mh, k), el = surface_error_pct(ml, k);
        std::cout << name << ": hull " << eh << " %, lofted " << el << " % of the diagonal\n";
        EXPECT_LT(el, 1.0) << name;
        EXPECT_LE(el, eh) << name;
        EXPECT_TRUE(check_mesh(ml).closed_manifold()) << name;
        for (int a = 0; a < 3; ++a) EXPECT_EQ(columns(*hull, a), columns(*out, a)) << name << ", axis " << a;
    }
}

// A box, a standing cylinder and a wedge keep their flat faces: the views' straight walls
// meet the view along them at its outline, so the lofted section is the hull's.
TEST(HullLoft, HardSurfacesKeepFlatFaces) {
    for (const auto& [name, k] : hard_shapes()) {
        auto out = lofted(k, 96, 1.0);
        const Mesh m = marching_cubes(*out).value;
        const double flat = area_within_pct(m, k, 2.0);
        std::cout << name << ": " << flat << " % of the area within 2 deg of the true normal\n";
        EXPECT_GE(flat, 95.0) << name;
        EXPECT_LT(surface_error_pct(m, k), 0.5) << name;
    }
}

// Share 0 is the profile prior as it was, voxel for voxel.
TEST(HullLoft, ShareZeroIsTheProfilePrior) {
    const Known k = ellipsoid({1.0, 0.6, 0.8});
    std::shared_ptr<const Volume> hull;
    auto a = lofted(k, 48, 0.0, &hull);
    auto b = make_plausible(*hull, nullptr, {}).value;
    EXPECT_EQ(a->occupancy->activeVoxelCount(), b->occupancy->activeVoxelCount());
    auto diff = a->occupancy->deepCopy();
    diff->tree().topologyDifference(b->occupancy->tree());
    EXPECT_EQ(diff->activeVoxelCount(), 0u);
}

namespace {

// The known shape drawn from front, right and top (1024 px, 3 px per cell at 256) run through
// a bundled pipeline's nodes (pipelines/loft.yaml unless named) from the hull to the mesh it
// writes, each stage with the file's own parameters (the nodes that write, preview and score
// are left out): the meshes of its nodes by id, "write" the model a user of that pipeline gets
// from such drawings.
std::map<std::string, Mesh> through_pipeline(const Known& k, const char* pipeline = "loft.yaml") {
    const YAML::Node file = YAML::LoadFile((source_dir() / "pipelines" / pipeline).string());
    const double scale = 800.0 / std::max({k.hi[0] - k.lo[0], k.hi[1] - k.lo[1], k.hi[2] - k.lo[2]});
    std::vector<View> vs;
    for (const char* n : {"front", "right", "top"})
        vs.push_back(ortho_view(n, 1024, scale, k.outline(*Camera::named(n))));
    std::map<std::string, Data> out;
    for (const auto& node : file["nodes"]) {
        const auto id = node["id"].as<std::string>(), stage = node["stage"].as<std::string>();
        if (stage == "views.load") {
            out[id] = Data(std::shared_ptr<const Views>(make_views(vs, k.lo, k.hi)));
            continue;
        }
        if (stage == "mesh.write") {
            std::map<std::string, Mesh> meshes;
            for (const auto& [n, d] : out)
                if (const auto* m = std::get_if<std::shared_ptr<const Mesh>>(&d)) meshes[n] = **m;
            meshes["write"] = meshes.at(node["inputs"]["mesh"].as<std::string>());
            return meshes;
        }
        if (stage.rfind("eval.", 0) == 0) continue;
        StageHarness h(stage);
        if (node["params"]) {
            YAML::Emitter e;
            e << YAML::Flow << node["params"];
            h.params(e.c_str());
        }
        for (const auto& in : node["inputs"])
            std::visit(
                [&](const auto& d) {
                    if constexpr (!std::is_same_v<std::decay_t<decltype(d)>, std::monostate>)
                        h.input(in.first.as<std::string>(), d);
                },
                out.at(in.second.as<std::string>()));
        out[id] = h.run_data();
    }
    ADD_FAILURE() << "pipelines/" << pipeline << " writes no mesh";
    return {};
}

} // namespace

// pipelines/loft.yaml as it is (its hull.plausible node's loft, hard_surface and ghost, its
// resolution, smoothing and reduction) on the shapes whose answer is known. The round ones come
// back within 1 % of their diagonal (over the written mesh's area: the per-vertex mean of the
// cone's reduced mesh is 1.03 %, its vertices kept at the apex and rim). The hard ones keep flat
// faces: the volume (its Marching Cubes mesh) over 95 % of the area within 2 deg of the true
// normal, and so the written box and wedge, and the written cylinder's flat caps (its side is
// faceted by the 20-degree reduction): the smoothing holds their sharp creases (`creases`) and
// the reduction removes crease vertices along their crease (`crease_straightness`).
TEST(HullLoft, LoftYamlOnShapesWhoseAnswerIsKnown) {
    for (const auto& [name, k] : round_shapes()) {
        const auto m = through_pipeline(k);
        const double e = area_error_pct(m.at("write"), k);
        std::cout << name << ": loft.yaml " << e << " % of the diagonal (vertices "
                  << surface_error_pct(m.at("write"), k) << " %, Marching Cubes " << area_error_pct(m.at("surface"), k)
                  << " %)\n";
        EXPECT_LT(e, 1.0) << name;
        EXPECT_TRUE(check_mesh(m.at("write")).closed_manifold()) << name;
    }
    // The faces whose true normal is vertical: the cylinder's caps, the box's top and bottom.
    auto caps = [](const Vec3d& n) { return std::abs(n[1]) > 0.99; };
    for (const auto& [name, k] : hard_shapes()) {
        const auto m = through_pipeline(k);
        const double volume = area_within_pct(m.at("surface"), k, 2.0),
                     written = area_within_pct(m.at("write"), k, 2.0),
                     written_caps = area_within_pct(m.at("write"), k, 2.0, caps);
        std::cout << name << ": loft.yaml's volume " << volume << " %, smoothed "
                  << area_within_pct(m.at("smooth"), k, 2.0) << " % (caps "
                  << area_within_pct(m.at("smooth"), k, 2.0, caps) << " %), the written mesh " << written << " % (caps "
                  << written_caps << " %) of the area within 2 deg of the true normal; "
                  << area_error_pct(m.at("write"), k) << " % of the diagonal, " << m.at("write").face_count()
                  << " faces\n";
        EXPECT_GE(volume, 95.0) << name;
        if (std::string(name) == "cylinder") {
            EXPECT_GE(written_caps, 95.0) << name << ": its flat caps";
        } else {
            EXPECT_GE(written, 95.0) << name;
        }
        EXPECT_LT(area_error_pct(m.at("write"), k), 0.1) << name;
        EXPECT_TRUE(check_mesh(m.at("write")).closed_manifold()) << name;
    }
}

// On a machined part pipelines/loft.yaml writes pipelines/paper.yaml's mesh, vertex for vertex:
// hull.plausible keeps the hull (hard_surface), and the smoothing and the reduction, told the
// same by their `hard_surface`, hold no crease and collapse along straight creases only, as
// paper.yaml's do (the hull's creases are where two drawings' outlines meet: a crease held
// there keeps the hull at its widest about the part, and fandisk seen from between the views
// was 0.06 points worse than paper.yaml's). The cylinder, whose top view is a disc, is no
// machined part: its creases are held (its caps, HullLoft.LoftYamlOnShapesWhoseAnswerIsKnown),
// and its mesh is not paper.yaml's.
TEST(HullLoft, OnAMachinedPartLoftYamlWritesPaperYamlsMesh) {
    for (const auto& [name, k] : hard_shapes()) {
        const Mesh loft = through_pipeline(k).at("write"), paper = through_pipeline(k, "paper.yaml").at("write");
        const bool same = loft.positions == paper.positions && loft.triangles == paper.triangles;
        if (std::string(name) == "cylinder") {
            EXPECT_FALSE(same) << name << ": its creases are held";
        } else {
            EXPECT_TRUE(same) << name << ": " << loft.face_count() << " faces against paper.yaml's "
                              << paper.face_count();
        }
    }
}
