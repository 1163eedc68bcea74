// A texture atlas made of charts per projection direction: the faces projected along
// one direction (a view's, for the faces that view sees best) and connected through
// shared edges form one chart; for an orthographic view that projection is the view's
// own image of those faces, free of distortion for the faces it sees squarely. The
// charts are packed as rectangles, `padding` texels apart, into one square image.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "core/mesh.h"

namespace cm {

/// A projection: a point p goes to (p . r, p . u); d points into the surfaces it is for.
struct ChartFrame {
    Vec3d r, u, d;
};

struct AtlasChart {
    int frame = 0;
    std::vector<std::uint32_t> faces;
    double lo_a = 0, lo_b = 0, hi_a = 0, hi_b = 0; ///< projected box, world units
    int x = 0, y = 0, w = 0, h = 0;                ///< its rectangle in texels, padding included
};

struct Atlas {
    int size = 0;               ///< the image is size x size texels
    int padding = 0;            ///< texels kept free around each chart
    double texels_per_unit = 0; ///< one scale for all charts: even texel density
    std::vector<AtlasChart> charts;
    std::vector<int> face_chart;                  ///< chart of each face
    std::vector<std::array<float, 2>> corner_uvs; ///< 3 per face, as Mesh::corner_uvs (v up)
};

/// @brief Moves the faces of islands of fewer than `min_faces` faces to the frame most of
/// their neighbours use, where `allowed(face, frame)` permits (slivers along chart borders).
void merge_small_islands(const Mesh& mesh, std::vector<int>& face_frame, int min_faces,
                         const std::function<bool(std::uint32_t, int)>& allowed);

/// @brief Charts from the faces' frames, packed at the largest even texel density that fits.
/// @throw cm::Error when the charts cannot fit at any density (too many for `size`).
Atlas build_atlas(const Mesh& mesh, const std::vector<ChartFrame>& frames, const std::vector<int>& face_frame, int size,
                  int padding);

/// Connected components of faces through edges shared by faces of the same label.
std::vector<std::vector<std::uint32_t>> label_components(const Mesh& mesh, const std::vector<int>& label);

} // namespace cm
