#include "texture_views.h"

#include <algorithm>
#include <cmath>

namespace cm::test {

View painted_view(const std::string& name, int size, double scale, const Outline& outline,
                  const std::function<Rgb(const Vec3d& q)>& fill) {
    View v = ortho_view(name, size, scale, outline);
    v.image.width = v.image.height = size;
    v.image.channels = 4;
    v.image.pixels.assign(std::size_t(size) * size * 4, 1.0f);
    for (int j = 0; j < size; ++j)
        for (int i = 0; i < size; ++i) {
            const float c = v.coverage_at(i, j);
            const double a = (i + 0.5 - v.camera.cx) / scale, b = (v.camera.cy - (j + 0.5)) / scale;
            const Rgb f = fill(v.camera.r * a + v.camera.u * b);
            for (int k = 0; k < 3; ++k) v.image.at(i, j, k) = c * f[k] + (1 - c) * 1.0f;
        }
    return v;
}

void draw_ink(View& v, int width) {
    const int w = v.width, h = v.height;
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            if (!v.inside(i, j)) continue;
            bool border = false;
            for (int dy = -width; dy <= width && !border; ++dy)
                for (int dx = -width; dx <= width; ++dx)
                    if (dx * dx + dy * dy <= width * width && !v.inside(i + dx, j + dy)) {
                        border = true;
                        break;
                    }
            const bool stroke = j >= h / 2 - width / 2 && j < h / 2 - width / 2 + width;
            if (border || stroke)
                for (int k = 0; k < 3; ++k) v.image.at(i, j, k) = 0.05f;
        }
}

Rgb texel(const Image& t, float u, float v) {
    const int x = std::clamp(int(u * t.width), 0, t.width - 1);
    const int y = std::clamp(int((1.0f - v) * t.height), 0, t.height - 1);
    return {t.at(x, y, 0), t.at(x, y, 1), t.at(x, y, 2)};
}

std::array<float, 2> uv_at(const Mesh& m, std::size_t f, double b0, double b1, double b2) {
    const auto &a = m.corner_uvs[3 * f], &b = m.corner_uvs[3 * f + 1], &c = m.corner_uvs[3 * f + 2];
    return {float(b0 * a[0] + b1 * b[0] + b2 * c[0]), float(b0 * a[1] + b1 * b[1] + b2 * c[1])};
}

double max_diff(const Rgb& a, const Rgb& b) {
    return std::max({std::abs(a[0] - b[0]), std::abs(a[1] - b[1]), std::abs(a[2] - b[2])});
}

} // namespace cm::test
