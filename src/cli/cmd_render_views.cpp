// conceptmesh render-views: synthetic concept art (or masks) of a mesh, with a views
// manifest whose cameras are exact.
#include <array>
#include <iostream>

#include "cli/commands.h"
#include "cli/tool_common.h"
#include "core/error.h"
#include "io/file_commit.h"
#include "io/image_io.h"
#include "io/limits.h"
#include "io/manifest.h"
#include "render/raster.h"
#include "render/shade.h"

namespace fs = std::filesystem;

namespace cm::cli {

namespace {

struct RenderViewsOptions {
    std::string mesh, out, views = "front,right,top", style = "art";
    AxisOptions axes;
    int size = 1024;
    unsigned seed = 1;
    std::string line_colour = "#1f3f8f"; ///< blueprint style
    double line_width = 1.5;             ///< blueprint style, pixels
    std::string paper = "white";         ///< blueprint style
    double grain = 0;                    ///< blueprint style: the paper's grain, +- this on each channel
};

// "#rrggbb" or a name (white, black, blue, red, grey) as RGB in [0, 1]; a bad one is an
// error naming `flag`.
std::array<float, 3> parse_colour(const std::string& s, const std::string& flag) {
    if (s == "white") return {1.0f, 1.0f, 1.0f};
    if (s == "black") return {0.05f, 0.05f, 0.06f};
    if (s == "blue") return {0.12f, 0.25f, 0.56f};
    if (s == "red") return {0.75f, 0.12f, 0.1f};
    if (s == "grey" || s == "gray") return {0.45f, 0.45f, 0.47f};
    if (s.size() == 7 && s[0] == '#' && s.find_first_not_of("0123456789abcdefABCDEF", 1) == std::string::npos) {
        std::array<float, 3> c{};
        for (int k = 0; k < 3; ++k)
            c[std::size_t(k)] = float(std::stoi(s.substr(1 + 2 * std::size_t(k), 2), nullptr, 16)) / 255.0f;
        return c;
    }
    throw Error(flag + " must be #rrggbb, white, black, blue, red or grey, got \"" + s + "\"");
}

// The drawing options of a style: art as it was; blueprint: lines only (the outline and
// every crease and inner contour) in the line colour and width on the paper (white unless
// told, with grain as a scan of paper has it), no fill.
ArtOptions style_options(const RenderViewsOptions& o) {
    ArtOptions art;
    art.seed = o.seed;
    if (o.style != "blueprint") return art;
    art.paper = parse_colour(o.paper, "--paper");
    art.fill = art.paper;
    art.shade = false;
    art.grain = float(o.grain);
    art.vignette = 0;
    art.ink = parse_colour(o.line_colour, "--line-colour");
    art.outline_px = float(o.line_width);
    art.outline_centred = true; // inked on the edge, as drawn by hand or by a CAD program
    art.crease_px = float(o.line_width);
    return art;
}

void write_image_atomic(const Image& img, const fs::path& file) {
    FileCommit files;
    write_image(img, files.stage(file));
    files.commit();
}

// The mask as a one-channel image.
Image mask_image(const std::vector<std::uint8_t>& mask, int size) {
    Image img;
    img.width = img.height = size;
    img.channels = 1;
    img.pixels.assign(mask.begin(), mask.end());
    return img;
}

// A drawing on paper: the art without its (opaque) alpha.
Image art_image(const Mesh& mesh, const Camera& cam, int size, const ArtOptions& art) {
    const Image img = render_art(mesh, cam, size, size, art);
    Image rgb;
    rgb.width = img.width;
    rgb.height = img.height;
    rgb.channels = 3;
    rgb.pixels.resize(std::size_t(img.width) * img.height * 3);
    for (std::size_t i = 0; i < std::size_t(img.width) * img.height; ++i)
        for (int k = 0; k < 3; ++k) rgb.pixels[i * 3 + std::size_t(k)] = img.pixels[i * 4 + std::size_t(k)];
    return rgb;
}

bool touches_border(const std::vector<std::uint8_t>& m, int size) {
    bool touches = false;
    for (int i = 0; i < size && !touches; ++i)
        touches = m[std::size_t(i)] || m[std::size_t(size - 1) * size + i] || m[std::size_t(i) * size] ||
                  m[std::size_t(i) * size + size - 1];
    return touches;
}

std::string manifest_comment(const RenderViewsOptions& o) {
    return "Written by conceptmesh render-views from " + fs::path(o.mesh).filename().string() + " (style " + o.style +
           ", " + std::to_string(o.size) + " px, up " + o.axes.up + ", front " + o.axes.front +
           ").\n"
           "Framing: bounding-box centre at the image centre, 0.9 * size / largest extent px per unit.\n"
           "The cameras are exact: per view, scale (px per world unit) and origin (image point of the\n"
           "world origin). The world is Y up, front +Z, origin at the bottom centre of the model's\n"
           "bounding box, in the model's units; bounds is that box. Delete scale, origin and bounds to\n"
           "have views.load align the views from their silhouettes instead, as it does for drawings.\n";
}

// Renders one view into `dir` and gives its manifest entry.
ManifestView render_view(const Mesh& mesh, const ViewSpec& s, const RenderViewsOptions& o, const fs::path& dir,
                         const GlobalOptions& g) {
    Vec3f lo, hi;
    mesh.bounds(lo, hi);
    const Camera cam = framed_camera(s.dir, Vec3d(lo), Vec3d(hi), o.size, o.size);
    const auto mask = render_mask(mesh, cam, o.size, o.size);
    const ArtOptions art = style_options(o);
    const Image img = o.style == "mask" ? mask_image(mask, o.size) : art_image(mesh, cam, o.size, art);
    // An object cut by the image border cannot be extracted faithfully.
    if (touches_border(mask, o.size) && !g.quiet)
        print_warning("view \"" + s.name +
                      "\": the object reaches the image border (the framing fits the "
                      "bounding box's largest extent, which an oblique view can exceed)");
    ManifestView v;
    v.key = s.name;
    v.image = dir / (s.name + ".png");
    write_image_atomic(img, v.image);
    if (s.named) v.view = s.name;
    else {
        v.azimuth = s.az;
        v.elevation = s.el;
    }
    // The same camera in the world frame: the box's centre, (0, height / 2, 0) there, at
    // the image centre.
    const Vec3d box_mid{0, 0.5 * (double(hi.y) - double(lo.y)), 0};
    v.scale = cam.scale;
    v.origin = {0.5 * o.size - cam.scale * dot(box_mid, cam.r), 0.5 * o.size + cam.scale * dot(box_mid, cam.u)};
    if (!g.quiet) std::cerr << "conceptmesh: wrote " << v.image.string() << "\n";
    return v;
}

int run_render_views(const RenderViewsOptions& o, const GlobalOptions& g) {
    const Orientation orient = o.axes.parse();
    const std::vector<ViewSpec> specs = parse_views(o.views);
    // Bytes per pixel at the peak, measured at 4096 px: 9 for masks, 50 for art (the
    // shading keeps depth, normals and float colour per pixel).
    const double per_pixel = o.style == "mask" ? 10 : 52;
    if (o.style == "blueprint") style_options(o); // a bad colour before any work
    check_memory_estimate(std::uint64_t(per_pixel * double(o.size) * double(o.size)),
                          "render-views at " + std::to_string(o.size) + " px (" + o.style + ")", "lower --size");
    const Mesh mesh = load_oriented(o.mesh, orient);
    const fs::path dir = o.out;
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (!fs::is_directory(dir)) throw Error("cannot create output folder \"" + dir.string() + "\"");
    // The manifest's world is the output frame: the rotated mesh moved so that the bottom
    // centre of its bounding box is the origin, in the mesh's units.
    Vec3f lo, hi;
    mesh.bounds(lo, hi);
    const Vec3d pivot = box_pivot(lo, hi), box_lo = Vec3d(lo) - pivot, box_hi = Vec3d(hi) - pivot;
    Manifest m;
    m.comment = manifest_comment(o);
    m.bounds = {box_lo.x, box_lo.y, box_lo.z, box_hi.x, box_hi.y, box_hi.z};
    for (const auto& s : specs) m.views.push_back(render_view(mesh, s, o, dir, g));
    const fs::path manifest = dir / "views.yaml";
    write_manifest(manifest, m);
    if (!g.quiet) std::cerr << "conceptmesh: wrote " << manifest.string() << "\n";
    return 0;
}

} // namespace

void add_render_views_command(CLI::App& app, GlobalOptions& g, std::function<int()>& action) {
    auto* cmd = app.add_subcommand(
        "render-views", "Render a mesh from named or azimuth/elevation views into images and a views.yaml manifest");
    auto o = std::make_shared<RenderViewsOptions>();
    cmd->add_option("mesh", o->mesh, "Mesh file (.obj .ply .stl .off)")->required();
    cmd->add_option("-o,--output", o->out, "Output folder (created if missing)")->required();
    cmd->add_option("--views", o->views,
                    "Comma-separated views: front back right left top bottom, or azAelE (az45el30)")
        ->capture_default_str();
    cmd->add_option("--size", o->size, "Image width and height in pixels")
        ->capture_default_str()
        ->check(CLI::Range(16, 16384));
    cmd->add_option("--style", o->style,
                    "mask: binary silhouettes; art: shaded drawing with outlines on paper; blueprint: line art "
                    "(outline, creases, part boundaries) in --line-colour and --line-width on --paper")
        ->capture_default_str()
        ->check(CLI::IsMember({"mask", "art", "blueprint"}));
    cmd->add_option("--line-colour", o->line_colour, "Blueprint style: line colour, #rrggbb or black, blue, red, grey")
        ->capture_default_str();
    cmd->add_option("--line-width", o->line_width, "Blueprint style: line width in pixels")
        ->capture_default_str()
        ->check(CLI::Range(0.5, 16.0));
    cmd->add_option("--paper", o->paper,
                    "Blueprint style: paper colour, #rrggbb or white (#f2ead8: scanned cream paper)")
        ->capture_default_str();
    cmd->add_option("--grain", o->grain, "Blueprint style: paper grain, uniform +- this on each channel (0: none)")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 0.2));
    o->axes.add_to(cmd, "The model's own up axis (+X -X +Y -Y +Z -Z)", "The model's own front axis (the way it faces)");
    cmd->add_option("--seed", o->seed, "Paper grain pattern (art style)")->capture_default_str();
    cmd->add_flag("-q,--quiet", g.quiet, "Only errors and warnings");
    set_action(cmd, action, [&g, o] { return run_render_views(*o, g); });
}

} // namespace cm::cli
