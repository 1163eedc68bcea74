// The one shape library of the tests and benchmarks: meshes, views drawn in code from
// exact outlines, and figures measured on volumes.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/views.h"
#include "core/volume.h"

namespace cm::test {

// ---- Meshes ------------------------------------------------------------------------

/// Closed, outward triangle meshes built in code.
Mesh make_box(Vec3f lo, Vec3f hi);
Mesh make_sphere(Vec3f centre, float radius, int subdivisions = 4); ///< icosphere
/// Appends `part`'s vertices and triangles to `into` (turned inside out when `flip`).
void append_mesh(Mesh& into, const Mesh& part, bool flip = false);
/// Two boxes that overlap: closed and 2-manifold, but their faces cross.
Mesh make_crossing_boxes();
/// make_box(lo, hi) with a flat cap: triangle 0's first edge (p, q) split at its middle M
/// into (p, M, r) and (M, q, r), and the face (p, q, M) of no area closing it: closed and
/// 2-manifold, one face with its corners on a line (the last face).
Mesh make_box_with_flat_cap(Vec3f lo, Vec3f hi);
/// A sphere with a box on its shoulder: lopsided, so a wrong axis or a mirror shows.
Mesh make_lopsided();

/// make_box(lo, hi) textured with six coloured blocks, 16 px each, 3 across and 2 down: side
/// s (triangles 2 s and 2 s + 1) has its per-corner UVs (v up) inside block s (column s % 3,
/// row s / 3 from the top), painted textured_box_colour(s). Its colours read upside down or
/// mirrored land on another side.
Mesh make_textured_box(Vec3f lo, Vec3f hi);
std::array<float, 3> textured_box_colour(int side);

/// Closed outward cube [lo, hi]^3 whose six faces are n x n grids of quads (two
/// triangles each), sharing vertices along the edges: 12 n^2 triangles.
Mesh make_grid_box(float lo, float hi, int n);

/// Moves every vertex along its direction from `centre` by a uniform random amount in
/// [-amplitude, amplitude] (fixed seed).
void add_radial_noise(Mesh& m, Vec3f centre, float amplitude, std::uint32_t seed = 1);

/// Front, right and top orthographic views (width x width px, framed so the box
/// [lo, hi]^3 spans 80 % of the image) of the axis-aligned box, with anti-aliased
/// coverage (4 x 4 samples per pixel).
Views make_box_views(float lo, float hi, int width);

/// Splits every triangle into four, `levels` times (positions at edge midpoints).
Mesh subdivide(const Mesh& m, int levels);

// ---- Views drawn from exact outlines, and volumes --------------------------------

/// A 2D outline in a view's image plane: signed distance (world units, positive inside)
/// of the plane point q = a r + b u (r, u the view's image axes, q . d = 0).
using Outline = std::function<double(const Vec3d& q)>;

/// Anti-aliased coverage with a soft ramp: 0.5 + signed distance / 3 px, clamped, so the
/// bilinear 0.5 iso-line is the outline to far below 0.05 px on straight and gently
/// curved edges.
double ramp_coverage(double signed_distance_px);

/// Orthographic named view (front, right, top, ...) of `size` x `size` pixels with
/// `scale` pixels per unit and the world origin at the image centre.
View ortho_view(const std::string& name, int size, double scale, const Outline& outline);

/// Views of the given names, with a bounding box.
std::shared_ptr<Views> make_views(std::vector<View> views, Vec3d lo, Vec3d hi);

/// Outlines of 3D shapes seen along a view's axis.
Outline sphere_outline(double radius);                 ///< a sphere at the origin
Outline box_outline(Vec3d lo, Vec3d hi, Vec3d view_d); ///< an axis-aligned box seen along view_d
Outline union_outline(Outline a, Outline b);

/// Perspective camera at `eye` looking at `target` with focal length `f` px and principal
/// point (cx, cy); image up is close to `up`.
std::array<double, 12> look_at(Vec3d eye, Vec3d target, Vec3d up, double f, double cx, double cy);
/// Perspective view of a sphere (centre c, radius r) through the 3x4 matrix.
View perspective_sphere_view(const std::string& name, const std::array<double, 12>& P, int w, int h, double f, Vec3d c,
                             double r);

/// Four perspective views (400 x 300, focal length f px) of a sphere (centre c, radius r)
/// from eyes about 6 units away on different sides: front, right, above and behind-left.
std::vector<View> perspective_sphere_ring(Vec3d c, double r, double f);

/// A w x h RGB drawing: `pen` where `ink(x, y)`, `paper` elsewhere, each pixel the mean of
/// 4 x 4 samples (anti-aliased, as a scan or a paint program gives it).
Image ink_drawing(int w, int h, const std::function<bool(double x, double y)>& ink, std::array<float, 3> pen,
                  std::array<float, 3> paper);

// ---- Turnaround sheets --------------------------------------------------------------

/// A turnaround sheet from separate drawings (RGB or RGBA, read as read_image() gives
/// them): side by side, `gap` pixels apart and top-aligned, over a strip `strip` pixels high
/// that holds under each drawing a text-like label (a row of five small dark blocks,
/// `strip` / 4 high). The gaps and the strip continue the nearest drawing's edge pixels, so
/// the paper is one sheet (no step in tone where two drawings meet).
Image compose_sheet(const std::vector<Image>& drawings, int gap, int strip);

/// IoU of a coverage image (inside where >= 0.5) and the region where `inside(x, y)`
/// holds at pixel centres; 1 when both are empty.
double coverage_iou(const std::vector<float>& coverage, int w, int h,
                    const std::function<bool(double x, double y)>& inside);

/// Grid points inside x voxel volume.
double counted_volume(const Volume& v);
/// Volume along x rows with the exact crossings at both ends of every run (O(h^2)).
double crossing_volume(const Volume& v);

} // namespace cm::test
