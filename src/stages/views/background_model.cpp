#include "background_model.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "io/manifest.h"

namespace cm {

namespace {

double dist_rgb(const Rgb& a, const Rgb& b) { return colour_distance(a, b); }

struct Sample {
    double u, v;
    Rgb c;
};

// Least squares of the quadratic on the samples marked in `use`; false when ill-posed.
bool fit_quadratic(const std::vector<Sample>& s, const std::vector<char>& use, BackgroundModel& m) {
    double A[6][6] = {};
    double B[3][6] = {};
    std::size_t n = 0;
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (!use[i]) continue;
        ++n;
        const auto b = BackgroundModel::basis(s[i].u, s[i].v);
        for (int r = 0; r < 6; ++r) {
            for (int c = 0; c < 6; ++c) A[r][c] += b[r] * b[c];
            for (int k = 0; k < 3; ++k) B[k][r] += b[r] * s[i].c[k];
        }
    }
    if (n < 24) return false;
    for (int r = 0; r < 6; ++r) A[r][r] += 1e-9 * double(n);
    // Gaussian elimination with partial pivoting, three right-hand sides.
    for (int col = 0; col < 6; ++col) {
        int piv = col;
        for (int r = col + 1; r < 6; ++r)
            if (std::abs(A[r][col]) > std::abs(A[piv][col])) piv = r;
        if (std::abs(A[piv][col]) < 1e-12 * double(n)) return false;
        if (piv != col) {
            for (int c = 0; c < 6; ++c) std::swap(A[col][c], A[piv][c]);
            for (int k = 0; k < 3; ++k) std::swap(B[k][col], B[k][piv]);
        }
        for (int r = col + 1; r < 6; ++r) {
            const double f = A[r][col] / A[col][col];
            for (int c = col; c < 6; ++c) A[r][c] -= f * A[col][c];
            for (int k = 0; k < 3; ++k) B[k][r] -= f * B[k][col];
        }
    }
    for (int k = 0; k < 3; ++k)
        for (int r = 5; r >= 0; --r) {
            double v = B[k][r];
            for (int c = r + 1; c < 6; ++c) v -= A[r][c] * m.coef[k][c];
            m.coef[k][r] = v / A[r][r];
        }
    return true;
}

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
}

} // namespace

void background_from_border(const Image& img, const std::string& option, BackgroundModel& model, double& noise,
                            std::vector<Rgb>& outliers, std::size_t& total) {
    const int w = img.width, h = img.height;
    const int band = std::max(1, std::min({2, w / 8, h / 8}));
    std::vector<Sample> s;
    const std::size_t perimeter = 2 * std::size_t(w + h) * std::size_t(band);
    const int stride = int(std::max<std::size_t>(1, perimeter / 40000));
    auto add = [&](int x, int y) {
        const auto p = img.rgba(std::size_t(y) * w + x);
        s.push_back({(x + 0.5) / w * 2 - 1, (y + 0.5) / h * 2 - 1, {p[0], p[1], p[2]}});
    };
    for (int b = 0; b < band; ++b) {
        for (int x = 0; x < w; x += stride) {
            add(x, b);
            add(x, h - 1 - b);
        }
        for (int y = band; y < h - band; y += stride) {
            add(b, y);
            add(w - 1 - b, y);
        }
    }
    Rgb fixed{};
    const bool given = option != "auto";
    if (given && !parse_background_colour(option, fixed)) check_background_option(option);
    Rgb med{};
    for (int k = 0; k < 3; ++k) {
        std::vector<double> c(s.size());
        for (std::size_t i = 0; i < s.size(); ++i) c[i] = s[i].c[k];
        med[k] = median(c);
    }
    model.set_constant(given ? fixed : med);
    std::vector<double> d(s.size());
    auto residuals = [&] {
        for (std::size_t i = 0; i < s.size(); ++i) d[i] = dist_rgb(s[i].c, model.at(s[i].u, s[i].v));
    };
    residuals();
    std::vector<char> use(s.size(), 1);
    if (!given) {
        // Robust refit: drop what the object (touching the border) contributes, fit again.
        for (int iter = 0; iter < 4; ++iter) {
            const double sigma = median(d);
            const double keep_below = std::max(3.0 * sigma, 0.03);
            for (std::size_t i = 0; i < s.size(); ++i) use[i] = d[i] <= keep_below;
            BackgroundModel trial = model;
            if (!fit_quadratic(s, use, trial)) break;
            model = trial;
            residuals();
        }
    }
    std::vector<double> kept;
    const double cut = std::max(3.0 * median(d), 0.03);
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (d[i] <= cut || given) kept.push_back(d[i]);
        else outliers.push_back(s[i].c);
    }
    total = s.size();
    noise = median(kept);
}

namespace {

// Whether the model is the same colour everywhere (a mask's black border), and that colour,
// `m`, as distance_row computes it: c[k][0] to the last bit wherever the pixel is (each
// further term adds a zero). A pixel's distance then depends on its colour alone, and runs
// of one colour (nearly all of a mask) reuse the distance of their first pixel.
bool constant_model(const BackgroundModel& model, double (&m)[3]) {
    for (int k = 0; k < 3; ++k)
        for (int i = 1; i < 6; ++i)
            if (model.coef[k][i] != 0.0) return false;
    for (int k = 0; k < 3; ++k) m[k] = 0.0 + model.coef[k][0] * 1.0;
    return true;
}

// distance_row for RGBA (or grey) bytes under a constant model: the runs of one colour are
// found on the pixels' RGB bytes, read four at a time (a grey pixel's one byte).
void constant_row_bytes(const double (&m)[3], int count, const std::uint8_t* b, double* out, int channels) {
    constexpr std::uint32_t kRgb = std::endian::native == std::endian::little ? 0x00FFFFFFu : 0xFFFFFF00u;
    // The distance as distance_row computes it: each further term of the model adds a zero.
    auto distance = [&](int x) {
        double sum = 0;
        for (int k = 0; k < 3; ++k) {
            const double d = double(float(b[channels * x + (channels == 1 ? 0 : k)]) * (1.0f / 255.0f)) - m[k];
            sum += d * d;
        }
        return std::sqrt(sum / 3.0);
    };
    auto runs = [&](auto&& colour_of) {
        for (int x = 0; x < count;) {
            const double d = distance(x);
            const auto colour = colour_of(x);
            out[x++] = d;
            while (x < count && colour_of(x) == colour) out[x++] = d;
        }
    };
    if (channels == 1) return runs([b](int x) { return b[x]; });
    runs([b](int x) {
        std::uint32_t p;
        std::memcpy(&p, b + 4 * std::size_t(x), 4);
        return p & kRgb;
    });
}

// model_distance_row over samples of one kind: `sample(x, k)` is channel k (red, green, blue)
// of pixel x of the row as a float.
// The row is row y of a window of `count` pixels starting at (ox, oy) in an image of nw x nh
// pixels (the window may be the whole image).
template <typename Sample>
void distance_row(const BackgroundModel& model, int count, int ox, int oy, int nw, int nh, int y, double* out,
                  Sample&& sample) {
    // The same operations in the same order as colour_distance(pixel, model.at(u, v)), so
    // each pixel's distance is the same double; only the loop is one the compiler can run
    // over several pixels at once (no arrays returned per pixel).
    const double v = ((y + oy) + 0.5) / nh * 2 - 1;
    const auto& c = model.coef;
    for (int x = 0; x < count; ++x) {
        const double u = ((x + ox) + 0.5) / nw * 2 - 1;
        const double uu = u * u, vv = v * v, uv = u * v;
        double sum = 0;
        for (int k = 0; k < 3; ++k) {
            double m = 0.0;
            m += c[k][0] * 1.0;
            m += c[k][1] * u;
            m += c[k][2] * v;
            m += c[k][3] * uu;
            m += c[k][4] * vv;
            m += c[k][5] * uv;
            const double d = double(sample(x, k)) - m;
            sum += d * d;
        }
        out[x] = std::sqrt(sum / 3.0);
    }
}

} // namespace

void BackgroundField::model_distance_row(const Image& img, int y, double* out) const {
    const int nc = img.channels;
    if (nc != 1 && nc != 4) { // other layouts (not read for drawings) through Image::rgba
        const std::size_t row = std::size_t(y) * std::size_t(w);
        distance_row(model, w, ox, oy, norm_w(), norm_h(), y, out,
                     [&](int x, int k) { return img.rgba(row + std::size_t(x))[std::size_t(k)]; });
        return;
    }
    const std::size_t row = std::size_t(y) * std::size_t(w) * std::size_t(nc);
    if (img.eight_bit()) {
        const std::uint8_t* b = img.bytes.data() + row;
        if (double m[3]; constant_model(model, m)) return constant_row_bytes(m, w, b, out, nc);
        if (nc == 1)
            return distance_row(model, w, ox, oy, norm_w(), norm_h(), y, out,
                                [b](int x, int) { return float(b[x]) * (1.0f / 255.0f); });
        distance_row(model, w, ox, oy, norm_w(), norm_h(), y, out,
                     [b](int x, int k) { return float(b[4 * x + k]) * (1.0f / 255.0f); });
    } else {
        const float* f = img.pixels.data() + row;
        if (nc == 1)
            return distance_row(model, w, ox, oy, norm_w(), norm_h(), y, out, [f](int x, int) { return f[x]; });
        distance_row(model, w, ox, oy, norm_w(), norm_h(), y, out, [f](int x, int k) { return f[4 * x + k]; });
    }
}

} // namespace cm
