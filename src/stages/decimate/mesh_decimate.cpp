#include "mesh_decimate.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "geometry/mesh_intersect.h"
#include "mesh_decimate_internal.h"

namespace cm {

namespace {

using decimate::Collapser;
using decimate::kPi;
using decimate::run_queue;

// One reduction run (see reduce_mesh).
DecimateStats reduce_once(Mesh& mesh, const ReduceOptions& opt, const std::vector<char>* frozen) {
    DecimateStats st;
    st.faces_before = mesh.face_count();
    Collapser c(mesh, frozen);
    st.locked_vertices = c.locked();
    const double limit = opt.max_angle_deg * kPi / 180.0;
    const double cos_limit = std::cos(limit);
    // Candidate test and importance: theta = the largest angle between two face normals
    // around v; I = theta * sum_j |V_j - V|. A small multiple of the perimeter orders
    // the exactly flat vertices (theta = 0) shortest-edges first.
    auto score = [&](std::uint32_t v, std::vector<std::uint32_t>&, float& key) {
        constexpr int kMax = 64;
        Vec3f normals[kMax];
        int n = 0;
        double L = 0;
        const Vec3f p = c.point(v);
        bool many = false;
        c.for_faces(v, [&](std::uint32_t f) {
            if (n == kMax) {
                many = true;
                return;
            }
            normals[n++] = c.normal(f);
            const auto& t = c.tri(f);
            const std::uint32_t next = t[0] == v ? t[1] : (t[1] == v ? t[2] : t[0]);
            L += length(c.point(next) - p);
        });
        if (many || n < 3) return false;
        float min_dot = 1.0f;
        for (int i = 0; i < n; ++i)
            for (int j = i + 1; j < n; ++j) min_dot = std::min(min_dot, dot(normals[i], normals[j]));
        const double theta = std::acos(std::clamp(double(min_dot), -1.0, 1.0));
        if (!(theta < limit)) return false;
        key = float(theta * L + 1e-4 * L);
        return true;
    };
    // The target: among the neighbours whose collapse passes the geometric guards, the one
    // that turns the faces least (then the nearest); topology is checked in that order.
    struct Option {
        double cos, len;
        std::uint32_t w;
    };
    std::vector<Option> options;
    auto choose = [&](std::uint32_t v, const std::vector<std::uint32_t>& rv, std::uint32_t& w, float&) {
        options.clear();
        const Vec3d p(c.point(v));
        for (auto x : rv) {
            double mc;
            if (!c.usable(x) || !c.geometry_ok(v, x, cos_limit, opt.max_aspect_ratio, mc)) continue;
            options.push_back({mc, length(Vec3d(c.point(x)) - p), x});
        }
        std::sort(options.begin(), options.end(), [](const Option& a, const Option& b) {
            if (std::fabs(a.cos - b.cos) > 1e-9) return a.cos > b.cos;
            return a.len < b.len;
        });
        for (const auto& o : options)
            if (c.topology_ok(v, o.w, rv)) {
                w = o.w;
                return true;
            }
        return false;
    };
    st.collapses = run_queue(c, mesh.positions.size(), opt.target_faces, HUGE_VALF, opt.progress, score, choose,
                             [](std::uint32_t, std::uint32_t, float) {});
    c.finish();
    st.faces_after = mesh.face_count();
    return st;
}

// Runs `once` and, while the result has faces crossing each other, runs it again from
// the input with the input vertices frozen where those faces cross (the overlap of the two
// faces' boxes, grown by a quarter). Frozen regions only grow and stay as the input had
// them, so the loop ends; it also stops when a restart removes nothing.
template <typename Once>
DecimateStats without_crossings(const Mesh& input, Mesh& mesh, bool enabled, Once&& once) {
    mesh = input;
    if (!enabled) return once(mesh, nullptr);
    constexpr std::size_t kMaxRestarts = 6;
    std::vector<char> frozen;
    std::size_t last = SIZE_MAX;
    for (std::size_t restart = 0;; ++restart) {
        DecimateStats st = once(mesh, restart ? &frozen : nullptr);
        const std::vector<FacePair> pairs = find_self_intersections(mesh);
        st.restarts = restart;
        st.crossings_left = pairs.size();
        st.frozen_vertices = std::size_t(std::count(frozen.begin(), frozen.end(), char(1)));
        if (pairs.empty() || restart == kMaxRestarts || pairs.size() >= last) return st;
        last = pairs.size();
        // The region of each crossing: where the two faces' boxes overlap, grown a little.
        std::vector<std::array<Vec3f, 2>> boxes;
        for (const auto& pr : pairs) {
            std::array<Vec3f, 2> fb[2];
            for (int i = 0; i < 2; ++i) {
                const auto& t = mesh.triangles[pr[std::size_t(i)]];
                fb[i] = {vmin(mesh.positions[t[0]], vmin(mesh.positions[t[1]], mesh.positions[t[2]])),
                         vmax(mesh.positions[t[0]], vmax(mesh.positions[t[1]], mesh.positions[t[2]]))};
            }
            const Vec3f lo = vmax(fb[0][0], fb[1][0]), hi = vmin(fb[0][1], fb[1][1]);
            const float small = std::min(length(fb[0][1] - fb[0][0]), length(fb[1][1] - fb[1][0]));
            const float grow = 0.25f * std::max(length(hi - lo), 0.25f * small);
            const Vec3f g(grow, grow, grow);
            boxes.push_back({lo - g, hi + g});
        }
        frozen.resize(input.positions.size(), 0);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, input.positions.size(), 4096), [&](const auto& r) {
            for (std::size_t v = r.begin(); v != r.end(); ++v) {
                const Vec3f& p = input.positions[v];
                for (const auto& b : boxes)
                    if (p.x >= b[0].x && p.x <= b[1].x && p.y >= b[0].y && p.y <= b[1].y && p.z >= b[0].z &&
                        p.z <= b[1].z) {
                        frozen[v] = 1;
                        break;
                    }
            }
        });
        mesh = input;
    }
}

} // namespace

DecimateStats reduce_mesh(const Mesh& input, Mesh& out, const ReduceOptions& opt) {
    return without_crossings(input, out, opt.no_crossings,
                             [&](Mesh& m, const std::vector<char>* frozen) { return reduce_once(m, opt, frozen); });
}

DecimateStats reduce_mesh(Mesh& mesh, const ReduceOptions& opt) {
    const Mesh input = std::move(mesh);
    return reduce_mesh(input, mesh, opt);
}

DecimateStats quadric_decimate(const Mesh& input, Mesh& out, const QuadricOptions& opt) {
    return without_crossings(input, out, opt.no_crossings, [&](Mesh& m, const std::vector<char>* frozen) {
        return decimate::quadric_once(m, opt, frozen);
    });
}

DecimateStats quadric_decimate(Mesh& mesh, const QuadricOptions& opt) {
    const Mesh input = std::move(mesh);
    return quadric_decimate(input, mesh, opt);
}

} // namespace cm
