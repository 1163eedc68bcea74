// Cameras of docs/conventions.md: named orthographic views,
// azimuth/elevation, and calibrated perspective 3x4 matrices. Pixel (i, j) covers
// [i,i+1) x [j,j+1).
#pragma once
#include <array>
#include <optional>
#include <string>

#include "core/vec.h"

namespace cm {

struct Camera {
    enum class Kind { Orthographic, Perspective };
    Kind kind = Kind::Orthographic;

    // Orthographic: x = cx + s (p . r), y = cy - s (p . u); d is the view direction.
    Vec3d r{1, 0, 0}, u{0, 1, 0}, d{0, 0, -1};
    double scale = 1.0;        ///< pixels per world unit
    double cx = 0.0, cy = 0.0; ///< image point of the world origin
    double azimuth_deg = 0, elevation_deg = 0;

    // Perspective: homogeneous pixel = P * [X Y Z 1].
    std::array<double, 12> P{};

    /// Orthographic camera looking from azimuth/elevation (degrees), unit scale, origin at (0,0).
    static Camera from_azimuth_elevation(double az_deg, double el_deg);
    /// front, back, right, left, top, bottom; std::nullopt for another name.
    static std::optional<Camera> named(const std::string& name);
    static Camera perspective(const std::array<double, 12>& P);

    bool orthographic() const { return kind == Kind::Orthographic; }
    /// Continuous pixel coordinates of a world point (perspective: divided by depth).
    Vec2d project(const Vec3d& p) const {
        if (kind == Kind::Orthographic) return {cx + scale * dot(p, r), cy - scale * dot(p, u)};
        const double x = P[0] * p.x + P[1] * p.y + P[2] * p.z + P[3];
        const double y = P[4] * p.x + P[5] * p.y + P[6] * p.z + P[7];
        const double w = P[8] * p.x + P[9] * p.y + P[10] * p.z + P[11];
        return {x / w, y / w};
    }
    /// Depth along the view direction (orthographic: p . d; perspective: the homogeneous w).
    double depth(const Vec3d& p) const;
    /// Perspective only: the camera centre (null space of P).
    Vec3d center() const;
    /// Ray through continuous pixel (x, y): origin and unit direction. Orthographic rays
    /// start on the plane p . d = 0 and run along d.
    void ray(double x, double y, Vec3d& origin, Vec3d& dir) const;
};

} // namespace cm
