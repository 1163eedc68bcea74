#include "mesh_shapes.h"

#include <map>
#include <random>
#include <unordered_map>

namespace cm::test {

Mesh make_grid_box(float lo, float hi, int n) {
    Mesh m;
    std::map<std::array<int, 3>, std::uint32_t> index;
    auto vertex = [&](std::array<int, 3> g) {
        auto [it, fresh] = index.emplace(g, std::uint32_t(m.positions.size()));
        if (fresh) {
            const float s = (hi - lo) / float(n);
            m.positions.push_back({lo + s * float(g[0]), lo + s * float(g[1]), lo + s * float(g[2])});
        }
        return it->second;
    };
    for (int a = 0; a < 3; ++a) {
        const int ua = (a + 1) % 3, va = (a + 2) % 3;   // e_u x e_v = e_a
        for (int side = 0; side < 2; ++side)
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < n; ++j) {
                    std::array<std::uint32_t, 4> q;
                    const int corners[4][2] = {{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}};
                    for (int c = 0; c < 4; ++c) {
                        std::array<int, 3> g{};
                        g[a] = side ? n : 0;
                        g[ua] = corners[c][0];
                        g[va] = corners[c][1];
                        q[c] = vertex(g);
                    }
                    if (side) {
                        m.triangles.push_back({q[0], q[1], q[2]});
                        m.triangles.push_back({q[0], q[2], q[3]});
                    } else {
                        m.triangles.push_back({q[0], q[2], q[1]});
                        m.triangles.push_back({q[0], q[3], q[2]});
                    }
                }
    }
    return m;
}

void add_radial_noise(Mesh& m, Vec3f centre, float amplitude, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-amplitude, amplitude);
    for (auto& p : m.positions) p = p + normalize(p - centre) * u(rng);
}

Views make_box_views(float lo, float hi, int width) {
    Views vs;
    const double scale = 0.8 * width / (hi - lo);
    const double mid = 0.5 * (lo + hi);
    for (const char* name : {"front", "right", "top"}) {
        View v;
        v.name = name;
        v.width = v.height = width;
        v.camera = *Camera::named(name);
        v.camera.scale = scale;
        // Put the box centre at the image centre.
        const Vec3d c{mid, mid, mid};
        v.camera.cx = 0.5 * width - scale * dot(c, v.camera.r);
        v.camera.cy = 0.5 * width + scale * dot(c, v.camera.u);
        // The box projects to the square [a, b]^2 in pixels.
        const double a = 0.5 * width - 0.5 * scale * (hi - lo), b = 0.5 * width + 0.5 * scale * (hi - lo);
        v.coverage.assign(std::size_t(width) * width, 0.0f);
        for (int y = 0; y < width; ++y)
            for (int x = 0; x < width; ++x) {
                int in = 0;
                for (int sy = 0; sy < 4; ++sy)
                    for (int sx = 0; sx < 4; ++sx) {
                        const double px = x + (sx + 0.5) / 4, py = y + (sy + 0.5) / 4;
                        in += px >= a && px < b && py >= a && py < b;
                    }
                v.coverage[std::size_t(y) * width + x] = float(in) / 16.0f;
            }
        vs.views.push_back(std::move(v));
    }
    vs.has_bounds = true;
    vs.bounds_min = {lo, lo, lo};
    vs.bounds_max = {hi, hi, hi};
    vs.units_per_pixel = 1.0 / scale;
    return vs;
}

Mesh subdivide(const Mesh& in, int levels) {
    Mesh m = in;
    m.normals.clear();
    m.uvs.clear();
    m.colors.clear();
    for (int l = 0; l < levels; ++l) {
        std::unordered_map<std::uint64_t, std::uint32_t> mid;
        mid.reserve(m.triangles.size() * 2);
        auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
            const std::uint64_t key = (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
            auto [it, fresh] = mid.emplace(key, std::uint32_t(m.positions.size()));
            if (fresh) m.positions.push_back((m.positions[a] + m.positions[b]) * 0.5f);
            return it->second;
        };
        std::vector<std::array<std::uint32_t, 3>> nf;
        nf.reserve(m.triangles.size() * 4);
        for (const auto& t : m.triangles) {
            const std::uint32_t a = midpoint(t[0], t[1]), b = midpoint(t[1], t[2]), c = midpoint(t[2], t[0]);
            nf.push_back({t[0], a, c});
            nf.push_back({t[1], b, a});
            nf.push_back({t[2], c, b});
            nf.push_back({a, b, c});
        }
        m.triangles.swap(nf);
    }
    return m;
}

} // namespace cm::test
