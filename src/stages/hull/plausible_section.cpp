// Lofted sections fitted to the view along their axis (plausible_section.h).
#include "plausible_section.h"

#include <algorithm>
#include <cmath>

namespace cm::plausible {

double FittedSection::norm(double pb, double pc, double exponent) const {
    const double db = pb - cb, dc = pc - cc;
    const double x = std::abs(db * eb + dc * ec) / r1, y = std::abs(-db * ec + dc * eb) / r2;
    if (exponent == 2.0) return std::sqrt(x * x + y * y);
    return std::pow(std::pow(x, exponent) + std::pow(y, exponent), 1.0 / exponent);
}

SectionMoments::SectionMoments(const std::array<Projection, 3>& proj) : proj_(proj) {
    for (std::size_t k = 0; k < 3; ++k) {
        const Projection& P = proj[k];
        const std::size_t w = std::size_t(P.nv) + 1;
        for (auto& m : t_[k].m) m.assign((std::size_t(P.nu) + 1) * w, 0.0);
        for (int iu = 0; iu < P.nu; ++iu)
            for (int iv = 0; iv < P.nv; ++iv) {
                const double in = P.in[std::size_t(iu) * std::size_t(P.nv) + std::size_t(iv)] ? 1.0 : 0.0;
                const double x = iu, y = iv;
                const double add[6] = {in, in * x, in * y, in * x * x, in * y * y, in * x * y};
                const std::size_t i11 = std::size_t(iu + 1) * w + std::size_t(iv + 1);
                const std::size_t i01 = std::size_t(iu) * w + std::size_t(iv + 1);
                const std::size_t i10 = std::size_t(iu + 1) * w + std::size_t(iv);
                const std::size_t i00 = std::size_t(iu) * w + std::size_t(iv);
                for (int q = 0; q < 6; ++q) {
                    std::vector<double>& m = t_[k].m[q];
                    m[i11] = m[i01] + m[i10] - m[i00] + add[q];
                }
            }
    }
}

FittedSection SectionMoments::fit(int a, const Interval& ib, const Interval& ic) const {
    const Projection& P = proj_[std::size_t(a)];
    const int b = (a + 1) % 3;
    // The box in the projection's (u, v), local.
    const Interval iu = b == P.u ? ib : ic, iv = b == P.u ? ic : ib;
    const int a0 = std::max(iu.lo - P.u0, 0), a1 = std::min(iu.hi - P.u0, P.nu - 1);
    const int b0 = std::max(iv.lo - P.v0, 0), b1 = std::min(iv.hi - P.v0, P.nv - 1);
    FittedSection s;
    if (a1 < a0 || b1 < b0) return s;
    const std::size_t w = std::size_t(P.nv) + 1;
    double m[6];
    for (int q = 0; q < 6; ++q) {
        const std::vector<double>& t = t_[std::size_t(a)].m[q];
        const auto at = [&](int i, int j) { return t[std::size_t(i) * w + std::size_t(j)]; };
        m[q] = at(a1 + 1, b1 + 1) - at(a0, b1 + 1) - at(a1 + 1, b0) + at(a0, b0);
    }
    const double n = m[0];
    if (n < 4.0) return s;
    const double mu = m[1] / n, mv = m[2] / n;
    // Covariance of the covered pixels (+ 1/12: a pixel's own extent).
    const double suu = m[3] / n - mu * mu + 1.0 / 12.0, svv = m[4] / n - mv * mv + 1.0 / 12.0;
    const double suv = m[5] / n - mu * mv;
    const double tr = suu + svv, det = std::max(suu * svv - suv * suv, 1e-9);
    const double disc = std::sqrt(std::max(0.25 * tr * tr - det, 0.0));
    const double l1 = 0.5 * tr + disc, l2 = std::max(0.5 * tr - disc, 1e-6);
    // The first axis's direction in (u, v).
    double du = 1.0, dv = 0.0;
    if (std::abs(suv) > 1e-12) {
        du = l1 - svv;
        dv = suv;
    } else if (svv > suu) {
        du = 0.0;
        dv = 1.0;
    }
    const double len = std::hypot(du, dv);
    du /= len;
    dv /= len;
    // One ellipse of these moments has area 4 pi sqrt(det) and half-axes 2 sqrt(l): the
    // covered area over it is about 1 for one blob (0.95 for a full box), small for blobs apart.
    s.compact = n / (4.0 * M_PI * std::sqrt(l1 * l2));
    // Its area: the covered area, no more than the ellipse inscribed in the box (a box the
    // view covers whole keeps the section it had).
    const double area = std::min(n, 0.25 * M_PI * double(iu.size()) * double(iv.size()));
    const double ratio = std::sqrt(l1 / l2);
    s.r2 = std::sqrt(area / (M_PI * ratio));
    s.r1 = s.r2 * ratio;
    const double cu = mu + P.u0, cv = mv + P.v0;
    if (b == P.u) {
        s.cb = cu, s.cc = cv, s.eb = du, s.ec = dv;
    } else {
        s.cb = cv, s.cc = cu, s.eb = dv, s.ec = du;
    }
    s.valid = true;
    return s;
}

} // namespace cm::plausible
