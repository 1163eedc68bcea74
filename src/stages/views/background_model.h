// The background of a drawing or photograph as the image border shows it: a smooth colour
// field (per channel a quadratic in the image coordinates) fitted robustly to the border.
#pragma once
#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "io/image_io.h"

namespace cm {

using Rgb = std::array<double, 3>;

/// RMS distance over the three channels, so a threshold reads as a fraction of full scale.
/// Inline: it runs for every pixel of every drawing.
inline double colour_distance(const Rgb& a, const Rgb& b) {
    const double dr = a[0] - b[0], dg = a[1] - b[1], db = a[2] - b[2];
    return std::sqrt((dr * dr + dg * dg + db * db) / 3.0);
}

/// A smooth background colour field over the image: per channel a quadratic in the
/// normalised coordinates (u, v) in [-1, 1], enough for paper tone and vignetting.
struct BackgroundModel {
    std::array<std::array<double, 6>, 3> coef{};
    static std::array<double, 6> basis(double u, double v) { return {1.0, u, v, u * u, v * v, u * v}; }
    Rgb at(double u, double v) const {
        const auto b = basis(u, v);
        Rgb c{};
        for (int k = 0; k < 3; ++k)
            for (int i = 0; i < 6; ++i) c[k] += coef[k][i] * b[i];
        return c;
    }
    void set_constant(const Rgb& c) {
        coef = {};
        for (int k = 0; k < 3; ++k) coef[k][0] = c[k];
    }
};

/// The background colour of each pixel of a w x h image: the model's, or, where `source`
/// names one (k + 1), the colour of another background found along the border (border
/// cluster k). Asked per pixel instead of kept in an image-sized array of colours (24 bytes a
/// pixel: 100 MB for a 2048 px view).
struct BackgroundField {
    BackgroundModel model;
    std::vector<Rgb> others;                            ///< the other backgrounds' colours
    const std::vector<unsigned char>* source = nullptr; ///< per pixel: 0 (the model) or k + 1
    int w = 0, h = 0;
    /// For a window of a larger image: where the window starts in it, and the whole image's
    /// size, which the model's coordinates are normalised to (0: w and h, the image itself).
    int ox = 0, oy = 0, full_w = 0, full_h = 0;
    int norm_w() const { return full_w ? full_w : w; }
    int norm_h() const { return full_h ? full_h : h; }
    Rgb of_model(int x, int y) const {
        return model.at(((x + ox) + 0.5) / norm_w() * 2 - 1, ((y + oy) + 0.5) / norm_h() * 2 - 1);
    }
    /// The colour distance of row y's pixels of `img` (RGBA, `w` of them) to the model, into
    /// `out`: colour_distance(pixel, of_model(x, y)) to the last bit, in one loop the compiler
    /// vectorises (it runs for every pixel of every drawing).
    void model_distance_row(const Image& img, int y, double* out) const;
    Rgb at(std::size_t i) const {
        const unsigned char s = source ? (*source)[i] : 0;
        if (s) return others[s - 1];
        return of_model(int(i % std::size_t(w)), int(i / std::size_t(w)));
    }
};

/// @brief Estimates the background field and its noise (the median distance of the border
/// to it) from a band along the image border; `option` is auto or a colour (which replaces
/// the fit). The border samples the field leaves out go to `outliers`, the number of
/// samples to `total`.
void background_from_border(const Image& img, const std::string& option, BackgroundModel& model, double& noise,
                            std::vector<Rgb>& outliers, std::size_t& total);

} // namespace cm
