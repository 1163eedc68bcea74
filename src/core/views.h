// The views passed between stages: drawings, their silhouettes, their cameras.
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/vec.h"

namespace cm {

/// Image, channels interleaved, row 0 at the top, samples in [0, 1]: float samples
/// (`pixels`: renders, textures, 16-bit and float sources), or the bytes of an 8-bit source
/// kept as they are (`bytes`: a drawing read by views.load, a quarter of the memory; read
/// through value()/rgba(), which give the same floats as converting it would).
struct Image {
    int width = 0, height = 0, channels = 0;
    std::vector<float> pixels;
    std::vector<std::uint8_t> bytes;
    bool eight_bit() const { return !bytes.empty(); }
    /// Sample k (pixel * channels + channel).
    float value(std::size_t k) const { return bytes.empty() ? pixels[k] : float(bytes[k]) * (1.0f / 255.0f); }
    /// Pixel i as RGBA, whatever the layout: grey (1 channel, or 2 with alpha) gives
    /// R = G = B, and a layout without alpha (1 or 3 channels) alpha 1.
    std::array<float, 4> rgba(std::size_t i) const {
        const std::size_t k = i * std::size_t(channels);
        if (channels == 4) {
            if (bytes.empty()) return {pixels[k], pixels[k + 1], pixels[k + 2], pixels[k + 3]};
            constexpr float s = 1.0f / 255.0f;
            return {float(bytes[k]) * s, float(bytes[k + 1]) * s, float(bytes[k + 2]) * s, float(bytes[k + 3]) * s};
        }
        if (channels >= 3) return {value(k), value(k + 1), value(k + 2), 1.0f};
        const float g = value(k);
        return {g, g, g, channels == 2 ? value(k + 1) : 1.0f};
    }
    std::size_t samples() const { return bytes.empty() ? pixels.size() : bytes.size(); }
    /// RGBA channel c (0 red, 1 green, 2 blue, 3 alpha) of pixel (x, y), as rgba() gives it.
    float at(int x, int y, int c) const { return rgba(std::size_t(y) * width + x)[std::size_t(c)]; }
    /// Float samples only (an image written into).
    float& at(int x, int y, int c) { return pixels[(std::size_t(y) * width + x) * channels + c]; }
    bool empty() const { return pixels.empty() && bytes.empty(); }
};

/// A silhouette's coverage in [0, 1] over a width x height image, row 0 at the top: stored
/// over a window, the box of its nonzero values, and zero beyond it (an object that fills a
/// third of a drawing keeps a third of the floats). Read by pixel (at, operator[]) or by
/// the window's rows; full() gives every value.
class Coverage {
public:
    Coverage() = default;
    /// The whole image's values, row-major; kept over the box of the nonzero ones.
    Coverage(const std::vector<float>& full, int width, int height);
    /// The values of a window w x h at (x0, y0) of a width x height image (row-major), zero
    /// beyond it; kept over the box of the nonzero ones.
    static Coverage of_window(const std::vector<float>& part, int width, int height, int x0, int y0, int w, int h);
    /// The same, keeping `part`'s own memory (no second array of the values).
    static Coverage of_window(std::vector<float>&& part, int width, int height, int x0, int y0, int w, int h);

    int width() const { return width_; }
    int height() const { return height_; }
    /// width * height: the image's pixel count (0: no coverage).
    std::size_t size() const { return std::size_t(width_) * std::size_t(height_); }
    bool empty() const { return size() == 0; }
    /// Pixel (x, y); 0 beyond the window (and beyond the image).
    float at(int x, int y) const {
        const unsigned dx = unsigned(x - x0_), dy = unsigned(y - y0_);
        return dx < unsigned(w_) && dy < unsigned(h_) ? values_[std::size_t(dy) * std::size_t(w_) + dx] : 0.0f;
    }
    /// Pixel i = y * width + x.
    float operator[](std::size_t i) const { return at(int(i % std::size_t(width_)), int(i / std::size_t(width_))); }
    /// The window: every nonzero value lies in x0 <= x < x0 + w, y0 <= y < y0 + h (w or h 0: none).
    int x0() const { return x0_; }
    int y0() const { return y0_; }
    int window_width() const { return w_; }
    int window_height() const { return h_; }
    /// The window's values, row-major (window_width() per row).
    const std::vector<float>& window_values() const { return values_; }
    /// The window's part of image row y (window_width() values from x0()); null for a row
    /// beyond the window.
    const float* window_row(int y) const {
        return unsigned(y - y0_) < unsigned(h_) ? values_.data() + std::size_t(y - y0_) * std::size_t(w_) : nullptr;
    }
    /// Every value, row-major.
    std::vector<float> full() const;
    /// A box of pixels, x0 <= x <= x1, y0 <= y <= y1 (empty when x1 < x0).
    struct Box {
        int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
        bool empty() const { return x1 < x0; }
    };
    /// The box of the pixels inside the silhouette (coverage >= 0.5); found when made.
    const Box& inside_box() const { return inside_; }

private:
    static Coverage frame(const std::vector<float>& part, int width, int height, int x0, int y0, int w, int h,
                          Box& nonzero);
    int width_ = 0, height_ = 0;
    int x0_ = 0, y0_ = 0, w_ = 0, h_ = 0;
    std::vector<float> values_;
    Box inside_;
};

struct View {
    std::string name;             ///< "front", "right", or the manifest key
    std::filesystem::path source; ///< image file it came from
    Image image;                  ///< the drawing: RGBA, or one channel (8-bit grey without alpha, as read)
    /// Silhouette as coverage in [0,1] over the image (width x height), kept over the box
    /// of its nonzero values. Anti-aliased edges keep fractional coverage for sub-pixel
    /// boundaries.
    Coverage coverage;
    int width = 0, height = 0;
    Camera camera;
    float coverage_at(int x, int y) const { return coverage.at(x, y); }
    bool inside(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height && coverage_at(x, y) >= 0.5f; }
};

struct Views {
    std::vector<View> views;
    std::filesystem::path manifest;
    /// True for calibrated perspective views: the world is the calibration's frame.
    bool calibrated = false;
    /// World-space box that holds the object (from alignment, or the manifest's `bounds`).
    bool has_bounds = false;
    Vec3d bounds_min, bounds_max;
    /// World units per pixel of the first view (1 unless the manifest gives a real size).
    double units_per_pixel = 1.0;
    /// Finest pixel size in world units over all views (sub-pixel tolerances use it).
    double finest_pixel() const;
};

} // namespace cm
