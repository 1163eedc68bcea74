// Garland-Heckbert quadric decimation (quadric_decimate in mesh_decimate.h): the
// ordering on the shared collapse engine.
#include "mesh_decimate_internal.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace cm::decimate {

namespace {

// Symmetric 4x4 quadric: a2 ab ac ad b2 bc bd c2 cd d2.
struct Quadric {
    double q[10] = {};
    void add_plane(const Vec3d& n, double d, double w) {
        const double a = n.x, b = n.y, c = n.z;
        const double v[10] = {a * a, a * b, a * c, a * d, b * b, b * c, b * d, c * c, c * d, d * d};
        for (int i = 0; i < 10; ++i) q[i] += w * v[i];
    }
    Quadric& operator+=(const Quadric& o) {
        for (int i = 0; i < 10; ++i) q[i] += o.q[i];
        return *this;
    }
    double eval(const Vec3d& p) const {
        const double x = p.x, y = p.y, z = p.z;
        return q[0] * x * x + 2 * q[1] * x * y + 2 * q[2] * x * z + 2 * q[3] * x + q[4] * y * y + 2 * q[5] * y * z +
               2 * q[6] * y + q[7] * z * z + 2 * q[8] * z + q[9];
    }
};

} // namespace

QuadricStats quadric_once(Mesh& mesh, const QuadricOptions& opt, const std::vector<char>* frozen,
                          const Progress& progress) {
    QuadricStats st;
    st.faces_before = mesh.face_count();
    const std::size_t nv = mesh.positions.size();
    // Plane quadrics, area weighted, summed per vertex.
    std::vector<Quadric> Q(nv);
    for (const auto& t : mesh.triangles) {
        const Vec3d a(mesh.positions[t[0]]), b(mesh.positions[t[1]]), cc(mesh.positions[t[2]]);
        const Vec3d n2 = cross_of(a, b, cc);
        const double len = length(n2);
        if (!(len > 0)) continue;
        const Vec3d n = n2 / len;
        for (int k = 0; k < 3; ++k) Q[t[k]].add_plane(n, -dot(n, a), 0.5 * len);
    }
    Collapser c(mesh, frozen);
    st.locked_vertices = c.locked();
    const double cos_limit = std::cos(opt.max_normal_deviation_deg * kPi / 180.0);
    const double max_err2 = opt.max_error > 0 ? opt.max_error * opt.max_error : HUGE_VAL;
    // Errors are normalised by the area of the quadric (sum of weights of the planes) so
    // that the key is a squared distance.
    auto cost = [&](std::uint32_t v, std::uint32_t w) {
        Quadric s = Q[v];
        s += Q[w];
        return std::max(0.0, s.eval(Vec3d(c.point(w))));
    };
    auto area_of = [&](std::uint32_t v, std::uint32_t w) {
        // q[0] + q[4] + q[7] = sum of weights * |n|^2 = total area weight
        return std::max(1e-30, Q[v].q[0] + Q[v].q[4] + Q[v].q[7] + Q[w].q[0] + Q[w].q[4] + Q[w].q[7]);
    };
    auto score = [&](std::uint32_t v, std::vector<std::uint32_t>& ring, float& key) {
        c.ring(v, ring);
        double best = HUGE_VAL;
        for (auto x : ring)
            if (c.usable(x)) best = std::min(best, cost(v, x) / area_of(v, x));
        if (!(best < HUGE_VAL)) return false;
        key = float(best);
        return true;
    };
    // The cheapest neighbour that passes the guards; costs first (cheap), checks in order.
    std::vector<std::pair<double, std::uint32_t>> options;
    std::vector<Collapser::OldFace> old;
    auto choose = [&](std::uint32_t v, const std::vector<std::uint32_t>& rv, std::uint32_t& w, float& key) {
        options.clear();
        for (auto x : rv)
            if (c.usable(x)) options.push_back({cost(v, x) / area_of(v, x), x});
        std::sort(options.begin(), options.end());
        if (!options.empty()) c.old_faces(v, old);
        for (const auto& [e, x] : options) {
            double mc;
            if (!c.geometry_ok(v, x, cos_limit, opt.max_aspect_ratio, mc, old) || !c.topology_ok(v, x, rv)) continue;
            w = x;
            key = std::max(key, float(e));
            return true;
        }
        return false;
    };
    double max_err = 0;
    st.collapses = run_queue(c, nv, opt.target_faces, float(max_err2), progress, score, choose,
                             [&](std::uint32_t v, std::uint32_t w, float key) {
                                 Q[w] += Q[v];
                                 max_err = std::max(max_err, double(key));
                             });
    c.finish();
    st.max_error = std::sqrt(max_err);
    st.faces_after = mesh.face_count();
    return st;
}

} // namespace cm::decimate
