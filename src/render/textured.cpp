#include "render/textured.h"

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "render/colour.h"
#include "render/raster.h"

namespace cm {

namespace {

// Bilinear texture lookup, v up (row 0 of the image is v = 1), clamped at the border.
std::array<float, 3> sample_texture(const Image& t, float u, float v) {
    const double fx = std::clamp(double(u) * t.width - 0.5, 0.0, double(t.width - 1));
    const double fy = std::clamp((1.0 - double(v)) * t.height - 0.5, 0.0, double(t.height - 1));
    const int x0 = int(fx), y0 = int(fy), x1 = std::min(x0 + 1, t.width - 1), y1 = std::min(y0 + 1, t.height - 1);
    const float ax = float(fx - x0), ay = float(fy - y0);
    std::array<float, 3> c{};
    for (int k = 0; k < 3; ++k)
        c[k] = (1 - ay) * ((1 - ax) * t.at(x0, y0, k) + ax * t.at(x1, y0, k)) +
               ay * ((1 - ax) * t.at(x0, y1, k) + ax * t.at(x1, y1, k));
    return c;
}

} // namespace

bool has_colour(const Mesh& m) {
    const bool uvs =
        m.corner_uvs.size() == m.triangles.size() * 3 || (!m.uvs.empty() && m.uvs.size() == m.positions.size());
    return (m.texture && !m.texture->empty() && uvs) || (!m.colors.empty() && m.colors.size() == m.positions.size());
}

Image render_colour(const Mesh& mesh, const Camera& cam, int width, int height, const std::array<float, 3>& background,
                    Progress progress) {
    const DepthImage d = render_depth(mesh, cam, width, height, progress);
    Image img;
    img.width = width;
    img.height = height;
    img.channels = 4;
    img.pixels.resize(std::size_t(width) * height * 4);
    const bool corner = mesh.corner_uvs.size() == mesh.triangles.size() * 3;
    const bool textured = mesh.texture && !mesh.texture->empty() &&
                          (corner || (!mesh.uvs.empty() && mesh.uvs.size() == mesh.positions.size()));
    const bool coloured = mesh.colors.size() == mesh.positions.size() && !mesh.colors.empty();
    tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
        progress.check();
        for (int y = rows.begin(); y < rows.end(); ++y)
            for (int x = 0; x < width; ++x) {
                float* px = &img.pixels[(std::size_t(y) * width + x) * 4];
                const std::uint32_t f = d.face[std::size_t(y) * width + x];
                if (f == DepthImage::kNoFace) {
                    px[0] = background[0];
                    px[1] = background[1];
                    px[2] = background[2];
                    px[3] = 0;
                    continue;
                }
                const auto& t = mesh.triangles[f];
                const Vec3d a(mesh.positions[t[0]]), b(mesh.positions[t[1]]), c(mesh.positions[t[2]]);
                const Vec3d n = cross(b - a, c - a);
                Vec3d o, dir;
                cam.ray(x + 0.5, y + 0.5, o, dir);
                const double den = dot(dir, n);
                Vec3d p = (a + b + c) / 3.0;
                if (std::abs(den) > 1e-300) p = o + dir * (dot(a - o, n) / den);
                const double nn = dot(n, n);
                double w[3] = {1.0 / 3, 1.0 / 3, 1.0 / 3};
                if (nn > 0) {
                    w[0] = std::clamp(dot(cross(b - p, c - p), n) / nn, 0.0, 1.0);
                    w[1] = std::clamp(dot(cross(c - p, a - p), n) / nn, 0.0, 1.0);
                    w[2] = std::max(0.0, 1.0 - w[0] - w[1]);
                }
                std::array<float, 3> col{0.8f, 0.8f, 0.8f};
                if (textured) {
                    float u = 0, v = 0;
                    for (int k = 0; k < 3; ++k) {
                        const auto& uv = corner ? mesh.corner_uvs[3 * f + k] : mesh.uvs[t[k]];
                        u += float(w[k]) * uv[0];
                        v += float(w[k]) * uv[1];
                    }
                    col = sample_texture(*mesh.texture, u, v);
                } else if (coloured) {
                    for (int ch = 0; ch < 3; ++ch) {
                        float s = 0;
                        for (int k = 0; k < 3; ++k) s += float(w[k]) * mesh.colors[t[k]][ch];
                        col[ch] = linear_to_srgb(s);
                    }
                }
                px[0] = col[0];
                px[1] = col[1];
                px[2] = col[2];
                px[3] = 1;
            }
    });
    return img;
}

} // namespace cm
