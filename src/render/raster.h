// Rasterising meshes through the cameras of docs/conventions.md: binary
// silhouettes (pixel centre inside a projected triangle), a depth/face buffer for
// shaded pictures, and the cameras that frame a mesh.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/mesh.h"
#include "core/progress.h"
#include "core/views.h"

namespace cm {

/// @brief Binary silhouette of a mesh seen through `cam`.
/// @return width*height bytes, row-major, row 0 at the top: 1 where a pixel centre
///         (i+0.5, j+0.5) lies inside a projected triangle (orthographic or perspective;
///         perspective triangles are clipped at the camera plane), else 0. A centre exactly
///         on an edge counts as inside, so triangles sharing an edge leave no gap.
/// TBB-parallel over triangles; millions of triangles in about a second. `progress` is
/// looked at per chunk of triangles (progress.check(), from worker threads at once).
std::vector<std::uint8_t> render_mask(const Mesh& mesh, const Camera& cam, int width, int height,
                                      Progress progress = {});

/// Nearest surface per pixel (pixel centre sampling, as render_mask).
struct DepthImage {
    int width = 0, height = 0;
    int x0 = 0, y0 = 0;              ///< where it lies in the image rendered (a window of it; 0, 0: the whole)
    std::vector<float> depth;        ///< Camera::depth of the nearest surface; +inf where empty
    std::vector<std::uint32_t> face; ///< triangle index of the nearest surface; kNoFace where empty
    static constexpr std::uint32_t kNoFace = 0xffffffffu;
    bool covered(int x, int y) const { return face[std::size_t(y) * width + x] != kNoFace; }
};

/// @brief Z-buffer render (TBB-parallel over image bands). The covered pixels are exactly
/// those render_mask() sets. `progress` is looked at per chunk of bands (progress.check()).
DepthImage render_depth(const Mesh& mesh, const Camera& cam, int width, int height, Progress progress = {});

/// A rectangle of pixels: columns [x0, x0 + width), rows [y0, y0 + height).
struct PixelWindow {
    int x0 = 0, y0 = 0, width = 0, height = 0;
};
/// @brief The pixels of a width x height image a mesh can cover through `cam` (pixel centre
/// sampling, as render_mask), with `rim` more on each side: the box of its projected vertices
/// (an orthographic view sees each face within it), within the image. The whole image for a
/// perspective view (a face crossing the camera plane is clipped there), when the box is not
/// finite, or when it misses the image.
PixelWindow covered_window(const Mesh& mesh, const Camera& cam, int width, int height, int rim = 0);
/// @brief The same over a window of the full_width x full_height image: the pixels, faces and
/// depths there are those of the whole image's render (the same tests at the same pixel
/// centres), from a window's memory and work. @throw cm::Error for a window beyond the image.
DepthImage render_depth(const Mesh& mesh, const Camera& cam, int full_width, int full_height, const PixelWindow& window,
                        Progress progress = {});

/// @brief Orthographic camera framed as docs/conventions.md "Rendering views of a mesh":
/// the box centre maps to (W/2, H/2) and s = 0.9 * min(W, H) / largest extent of the box.
/// `direction` gives r, u, d (and azimuth/elevation); its scale and origin are ignored.
/// @throw cm::Error for a perspective direction or an empty (zero-size) box.
Camera framed_camera(const Camera& direction, Vec3d bbox_min, Vec3d bbox_max, int width, int height);

/// @brief The same view for an image resized by `factor` (pixel (i, j) of the new image covers
/// [i, i+1) / factor of the old one): orthographic scale and origin, or the matrix's first two rows.
Camera resized_camera(const Camera& cam, double factor);

} // namespace cm
