#include "hull_shapes.h"

#include <algorithm>
#include <cmath>

namespace cm::test {

double ramp_coverage(double sd_px) { return std::clamp(0.5 + sd_px / 3.0, 0.0, 1.0); }

View ortho_view(const std::string& name, int size, double scale, const Outline& outline) {
    View v;
    v.name = name;
    v.camera = *Camera::named(name);
    v.camera.scale = scale;
    v.camera.cx = v.camera.cy = size / 2.0;
    v.width = v.height = size;
    v.coverage.resize(std::size_t(size) * size);
    for (int j = 0; j < size; ++j)
        for (int i = 0; i < size; ++i) {
            const double a = (i + 0.5 - v.camera.cx) / scale, b = (v.camera.cy - (j + 0.5)) / scale;
            const Vec3d q = v.camera.r * a + v.camera.u * b;
            v.coverage[std::size_t(j) * size + i] = float(ramp_coverage(outline(q) * scale));
        }
    return v;
}

std::shared_ptr<Views> make_views(std::vector<View> views, Vec3d lo, Vec3d hi) {
    auto vs = std::make_shared<Views>();
    vs->views = std::move(views);
    vs->has_bounds = true;
    vs->bounds_min = lo;
    vs->bounds_max = hi;
    return vs;
}

Outline sphere_outline(double radius) {
    return [radius](const Vec3d& q) { return radius - length(q); };
}

Outline box_outline(Vec3d lo, Vec3d hi, Vec3d d) {
    return [lo, hi, d](const Vec3d& q) {
        double sd = 1e300;
        for (int k = 0; k < 3; ++k) {
            if (std::abs(d[k]) > 0.5) continue;   // the viewing axis
            sd = std::min({sd, q[k] - lo[k], hi[k] - q[k]});
        }
        return sd;
    };
}

Outline union_outline(Outline a, Outline b) {
    return [a, b](const Vec3d& q) { return std::max(a(q), b(q)); };
}

std::array<double, 12> look_at(Vec3d eye, Vec3d target, Vec3d up, double f, double cx, double cy) {
    const Vec3d z = normalize(target - eye);          // camera forward
    const Vec3d x = normalize(cross(z, up));          // image right
    const Vec3d y = cross(z, x);                      // image down
    // P = K [R | -R eye], rows of R: x, y, z.
    const double t[3] = {-dot(x, eye), -dot(y, eye), -dot(z, eye)};
    const Vec3d R[3] = {x, y, z};
    std::array<double, 12> P{};
    for (int c = 0; c < 3; ++c) {
        P[c] = f * R[0][c] + cx * R[2][c];
        P[4 + c] = f * R[1][c] + cy * R[2][c];
        P[8 + c] = R[2][c];
    }
    P[3] = f * t[0] + cx * t[2];
    P[7] = f * t[1] + cy * t[2];
    P[11] = t[2];
    return P;
}

View perspective_sphere_view(const std::string& name, const std::array<double, 12>& P, int w, int h, double f,
                             Vec3d c, double r) {
    View v;
    v.name = name;
    v.camera = Camera::perspective(P);
    v.width = w;
    v.height = h;
    v.coverage.resize(std::size_t(w) * h);
    const Vec3d eye = v.camera.center();
    const double dist = length(c - eye);
    const double cone = std::asin(r / dist);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            Vec3d o, dir;
            v.camera.ray(i + 0.5, j + 0.5, o, dir);
            const double ang = std::acos(std::clamp(dot(dir, normalize(c - eye)), -1.0, 1.0));
            // Angle to pixels: about f pixels per radian near the centre of the image.
            v.coverage[std::size_t(j) * w + i] = float(ramp_coverage((cone - ang) * f));
        }
    return v;
}

double counted_volume(const Volume& v) {
    const double h = v.voxel_size();
    return double(v.occupancy->tree().activeVoxelCount()) * h * h * h;
}

double crossing_volume(const Volume& v) {
    const double h = v.voxel_size();
    double corr = 0;
    auto acc = v.occupancy->getConstAccessor();
    for (auto it = v.crossings->cbeginValueOn(); it; ++it) {
        const float t = (*it)[0];
        if (t < 0) continue;
        corr += acc.isValueOn(it.getCoord()) ? t - 0.5 : 0.5 - t;
    }
    return (double(v.occupancy->tree().activeVoxelCount()) + corr) * h * h * h;
}

} // namespace cm::test
