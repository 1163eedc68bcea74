#include "core/camera.h"

#include <cmath>

#include "core/error.h"

namespace cm {

namespace {
constexpr double kDeg = 3.14159265358979323846 / 180.0;
double snap(double v) { return std::abs(v) < 1e-12 ? 0.0 : v; }
Vec3d snap(const Vec3d& v) { return {snap(v.x), snap(v.y), snap(v.z)}; }
} // namespace

Camera Camera::from_azimuth_elevation(double az_deg, double el_deg) {
    const double az = az_deg * kDeg, el = el_deg * kDeg;
    Camera c;
    c.kind = Kind::Orthographic;
    const Vec3d cdir{std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el)};
    c.d = snap(-cdir);
    c.u = snap(Vec3d{-std::sin(az) * std::sin(el), std::cos(el), -std::cos(az) * std::sin(el)});
    c.r = snap(cross(c.d, c.u));
    c.azimuth_deg = az_deg;
    c.elevation_deg = el_deg;
    return c;
}

std::optional<Camera> Camera::named(const std::string& name) {
    if (name == "front") return from_azimuth_elevation(0, 0);
    if (name == "right") return from_azimuth_elevation(90, 0);
    if (name == "back") return from_azimuth_elevation(180, 0);
    if (name == "left") return from_azimuth_elevation(270, 0);
    if (name == "top") return from_azimuth_elevation(0, 90);
    if (name == "bottom") return from_azimuth_elevation(0, -90);
    return std::nullopt;
}

Camera Camera::perspective(const std::array<double, 12>& P) {
    Camera c;
    c.kind = Kind::Perspective;
    c.P = P;
    // Viewing direction: the third row's normal, oriented towards positive depth.
    Vec3d m3{P[8], P[9], P[10]};
    // det of the left 3x3 decides the sign (cameras with det<0 look along -m3).
    const double det =
        P[0] * (P[5] * P[10] - P[6] * P[9]) - P[1] * (P[4] * P[10] - P[6] * P[8]) + P[2] * (P[4] * P[9] - P[5] * P[8]);
    c.d = normalize(det >= 0 ? m3 : -m3);
    return c;
}

double Camera::depth(const Vec3d& p) const {
    if (kind == Kind::Orthographic) return dot(p, d);
    return P[8] * p.x + P[9] * p.y + P[10] * p.z + P[11];
}

Vec3d Camera::center() const {
    if (kind == Kind::Orthographic) throw Error("an orthographic camera has no centre");
    // C = -M^-1 p4 with M the left 3x3 of P.
    const double a = P[0], b = P[1], c = P[2], d_ = P[4], e = P[5], f = P[6], g = P[8], h = P[9], i = P[10];
    const double det = a * (e * i - f * h) - b * (d_ * i - f * g) + c * (d_ * h - e * g);
    if (std::abs(det) < 1e-300) throw Error("the camera matrix is singular");
    const double inv[9] = {(e * i - f * h) / det,  (c * h - b * i) / det, (b * f - c * e) / det,
                           (f * g - d_ * i) / det, (a * i - c * g) / det, (c * d_ - a * f) / det,
                           (d_ * h - e * g) / det, (b * g - a * h) / det, (a * e - b * d_) / det};
    const Vec3d p4{P[3], P[7], P[11]};
    return {-(inv[0] * p4.x + inv[1] * p4.y + inv[2] * p4.z), -(inv[3] * p4.x + inv[4] * p4.y + inv[5] * p4.z),
            -(inv[6] * p4.x + inv[7] * p4.y + inv[8] * p4.z)};
}

void Camera::ray(double x, double y, Vec3d& origin, Vec3d& dir) const {
    if (kind == Kind::Orthographic) {
        origin = r * ((x - cx) / scale) + u * ((cy - y) / scale);
        dir = d;
        return;
    }
    origin = center();
    // Solve M X = (x, y, 1) for a point on the ray, direction X (up to sign).
    const double a = P[0], b = P[1], c = P[2], d_ = P[4], e = P[5], f = P[6], g = P[8], h = P[9], i = P[10];
    const double det = a * (e * i - f * h) - b * (d_ * i - f * g) + c * (d_ * h - e * g);
    const double inv[9] = {(e * i - f * h) / det,  (c * h - b * i) / det, (b * f - c * e) / det,
                           (f * g - d_ * i) / det, (a * i - c * g) / det, (c * d_ - a * f) / det,
                           (d_ * h - e * g) / det, (b * g - a * h) / det, (a * e - b * d_) / det};
    Vec3d v{inv[0] * x + inv[1] * y + inv[2], inv[3] * x + inv[4] * y + inv[5], inv[6] * x + inv[7] * y + inv[8]};
    // Orient towards positive depth.
    if (depth(origin + v) < 0) v = -v;
    dir = normalize(v);
}

} // namespace cm
