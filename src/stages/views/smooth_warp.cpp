#include "smooth_warp.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Sparse>

namespace cm {

namespace {

// The four cubic B-spline weights at t in [0, 1).
std::array<double, 4> bspline(double t) {
    const double s = 1 - t, t2 = t * t, t3 = t2 * t;
    return {s * s * s / 6, (3 * t3 - 6 * t2 + 4) / 6, (-3 * t3 + 3 * t2 + 3 * t + 1) / 6, t3 / 6};
}

} // namespace

WarpField::WarpField(double x0, double y0, double x1, double y1, double h) : h_(h) {
    ox_ = x0 - 3 * h, oy_ = y0 - 3 * h;
    nx_ = int(std::ceil(std::max(0.0, x1 - x0) / h)) + 7;
    ny_ = int(std::ceil(std::max(0.0, y1 - y0) / h)) + 7;
    c_.assign(std::size_t(nx_) * std::size_t(ny_), Vec2d{0, 0});
}

Vec2d WarpField::operator()(double x, double y) const {
    const double u = (x - ox_) / h_, v = (y - oy_) / h_;
    const int i = int(std::floor(u)), j = int(std::floor(v));
    if (i < 0 || j < 0 || i + 3 >= nx_ || j + 3 >= ny_) return {0, 0};
    const auto bx = bspline(u - i), by = bspline(v - j);
    Vec2d d{0, 0};
    for (int l = 0; l < 4; ++l) {
        const Vec2d* row = c_.data() + std::size_t(j + l) * std::size_t(nx_) + std::size_t(i);
        double sx = 0, sy = 0;
        for (int k = 0; k < 4; ++k) sx += bx[std::size_t(k)] * row[k].x, sy += bx[std::size_t(k)] * row[k].y;
        d.x += by[std::size_t(l)] * sx, d.y += by[std::size_t(l)] * sy;
    }
    return d;
}

std::array<double, 4> WarpField::support() const { return {ox_, oy_, ox_ + (nx_ - 3) * h_, oy_ + (ny_ - 3) * h_}; }

void WarpField::fit(const std::vector<WarpTarget>& targets, double membrane) {
    // The free control points: all but the outer three rings.
    const int fx = nx_ - 6, fy = ny_ - 6;
    const int n = fx * fy;
    std::fill(c_.begin(), c_.end(), Vec2d{0, 0});
    if (n <= 0 || targets.empty()) return;
    auto free_id = [&](int I, int J) {
        return I >= 3 && J >= 3 && I < nx_ - 3 && J < ny_ - 3 ? (J - 3) * fx + (I - 3) : -1;
    };
    std::vector<Eigen::Triplet<double>> trip;
    Eigen::VectorXd rx = Eigen::VectorXd::Zero(n), ry = Eigen::VectorXd::Zero(n);
    double total = 0;
    for (const WarpTarget& t : targets) {
        const double u = (t.at.x - ox_) / h_, v = (t.at.y - oy_) / h_;
        const int i = int(std::floor(u)), j = int(std::floor(v));
        if (i < 0 || j < 0 || i + 3 >= nx_ || j + 3 >= ny_) continue;
        total += t.weight;
        const auto bx = bspline(u - i), by = bspline(v - j);
        std::array<std::pair<int, double>, 16> row;
        int m = 0;
        for (int l = 0; l < 4; ++l)
            for (int k = 0; k < 4; ++k)
                if (const int id = free_id(i + k, j + l); id >= 0)
                    row[std::size_t(m++)] = {id, bx[std::size_t(k)] * by[std::size_t(l)]};
        for (int a = 0; a < m; ++a) {
            const auto [ia, wa] = row[std::size_t(a)];
            rx[ia] += t.weight * wa * t.v.x, ry[ia] += t.weight * wa * t.v.y;
            for (int b = 0; b < m; ++b)
                trip.emplace_back(ia, row[std::size_t(b)].first, t.weight * wa * row[std::size_t(b)].second);
        }
    }
    if (total <= 0) return;
    // The membrane: each free point against its four neighbours (a held one counts as zero).
    const double s = membrane;
    for (int J = 3; J < ny_ - 3; ++J)
        for (int I = 3; I < nx_ - 3; ++I) {
            const int a = free_id(I, J);
            trip.emplace_back(a, a, 1e-9 * s);
            for (const auto& [dI, dJ] : {std::pair{1, 0}, std::pair{0, 1}, std::pair{-1, 0}, std::pair{0, -1}}) {
                const int b = free_id(I + dI, J + dJ);
                trip.emplace_back(a, a, s);
                if (b >= 0) trip.emplace_back(a, b, -s);
            }
        }
    Eigen::SparseMatrix<double> A(n, n);
    A.setFromTriplets(trip.begin(), trip.end());
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(A);
    if (ldlt.info() != Eigen::Success) return;
    const Eigen::VectorXd cx = ldlt.solve(rx), cy = ldlt.solve(ry);
    for (int J = 3; J < ny_ - 3; ++J)
        for (int I = 3; I < nx_ - 3; ++I) {
            const int a = free_id(I, J);
            c_[std::size_t(J) * std::size_t(nx_) + std::size_t(I)] = {cx[a], cy[a]};
        }
}

} // namespace cm
