// The views passed between stages: drawings, their silhouettes, their cameras.
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
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

struct View {
    std::string name;             ///< "front", "right", or the manifest key
    std::filesystem::path source; ///< image file it came from
    Image image;                  ///< the drawing: RGBA, or one channel (8-bit grey without alpha, as read)
    /// Silhouette as coverage in [0,1], width*height, row-major, row 0 at the top.
    /// Anti-aliased edges keep fractional coverage for sub-pixel boundaries.
    std::vector<float> coverage;
    int width = 0, height = 0;
    Camera camera;
    float coverage_at(int x, int y) const { return coverage[std::size_t(y) * width + x]; }
    bool inside(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height && coverage_at(x, y) >= 0.5f; }
};

/// Data a stage derives from the views and another stage needs again (the silhouettes'
/// distance fields: hull-constrained smoothing and the reduction's outline guard), kept with
/// the views so that it is built once per run. A copy of the views starts with none: what
/// was derived from one set of views is never handed out for another.
class DerivedData {
public:
    DerivedData() = default;
    DerivedData(const DerivedData&) {}
    DerivedData& operator=(const DerivedData&) {
        std::lock_guard<std::mutex> lock(mutex_);
        items_.clear();
        return *this;
    }
    /// The item under `key`, made by `make` when there is none yet. It is made once: a
    /// stage asking while another makes it helps with that one's parallel work
    /// (tbb::collaborative_call_once) and then has it. When `make` throws, nothing is kept
    /// and the next asker makes it.
    std::shared_ptr<const void> get(const std::string& key,
                                    const std::function<std::shared_ptr<const void>()>& make) const;

private:
    struct Slot;
    mutable std::mutex mutex_;
    mutable std::map<std::string, std::shared_ptr<Slot>> items_;
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
    /// Data derived from these views by a stage, for others to reuse (see DerivedData).
    DerivedData derived;
};

} // namespace cm
