// Tool commands that work on meshes and views outside a pipeline:
//   render-views  synthetic concept art (or masks) of a mesh, with a views manifest
//   compare       silhouette error of a mesh against a views manifest
//   preview       contact sheet of a mesh against its views
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <regex>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "core/error.h"
#include "io/image_io.h"
#include "io/mesh_io.h"
#include "render/raster.h"
#include "render/shade.h"
#include "io/file_commit.h"
#include "pipeline/run_stage.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace cm::cli {

namespace {

// "+Y", "-z", "Y" -> unit axis.
Vec3d parse_axis(const std::string& s, const char* option) {
    std::string t = s;
    double sign = 1;
    if (!t.empty() && (t[0] == '+' || t[0] == '-')) {
        sign = t[0] == '-' ? -1 : 1;
        t = t.substr(1);
    }
    if (t.size() == 1) {
        const char c = char(std::toupper(static_cast<unsigned char>(t[0])));
        if (c == 'X') return {sign, 0, 0};
        if (c == 'Y') return {0, sign, 0};
        if (c == 'Z') return {0, 0, sign};
    }
    throw Error(std::string(option) + " \"" + s + "\" is not an axis (use +X, -X, +Y, -Y, +Z or -Z)");
}

// The model's own up and front axes -> the conventions' frame (Y up, front +Z, X = Y x Z).
struct Orientation {
    Vec3d up{0, 1, 0}, front{0, 0, 1};
    bool identity() const { return up == Vec3d{0, 1, 0} && front == Vec3d{0, 0, 1}; }
    Vec3d apply(const Vec3d& p) const { return {dot(p, cross(up, front)), dot(p, up), dot(p, front)}; }
};

Orientation parse_orientation(const std::string& up, const std::string& front) {
    Orientation o;
    o.up = parse_axis(up, "--up");
    o.front = parse_axis(front, "--front");
    if (std::abs(dot(o.up, o.front)) > 0.5)
        throw Error("--up " + up + " and --front " + front + " must name two different axes");
    return o;
}

Mesh load_oriented(const std::string& file, const Orientation& o) {
    Mesh m = read_mesh(file);
    if (m.triangles.empty()) throw Error("mesh \"" + file + "\" has no triangles");
    if (!o.identity()) {
        for (auto& p : m.positions) p = Vec3f(o.apply(Vec3d(p)));
        for (auto& n : m.normals) n = Vec3f(o.apply(Vec3d(n)));
    }
    return m;
}

// Maps the mesh's bounding box onto the box the aligned views imply (per axis).
void fit_bbox(Mesh& m, const Views& views) {
    if (!views.has_bounds)
        throw Error("--fit bbox needs the box the views imply; these calibrated views give no bounds in their manifest");
    Vec3f lo, hi;
    m.bounds(lo, hi);
    for (auto& p : m.positions)
        for (int k = 0; k < 3; ++k) {
            const double ext = double(hi[k]) - double(lo[k]);
            const double t = ext > 0 ? (double(p[k]) - double(lo[k])) / ext : 0.5;
            p[k] = float(views.bounds_min[k] + t * (views.bounds_max[k] - views.bounds_min[k]));
        }
    m.normals.clear();
}

// Moves the mesh so its bounding box's bottom centre is at the origin (the output frame's
// pivot), keeping its size.
void fit_pivot(Mesh& m) {
    Vec3f lo, hi;
    m.bounds(lo, hi);
    const Vec3d pivot{0.5 * (double(lo.x) + double(hi.x)), double(lo.y), 0.5 * (double(lo.z) + double(hi.z))};
    for (auto& p : m.positions) p = Vec3f(Vec3d(p) - pivot);
}

void fit_mesh(Mesh& m, const Views& views, const std::string& fit) {
    if (fit == "bbox") fit_bbox(m, views);
    else if (fit == "pivot") fit_pivot(m);
}

struct ViewSpec {
    std::string name;   ///< file stem and manifest key
    Camera dir;
    bool named = false;
    double az = 0, el = 0;
};

// "front,right,top,az45el30,az-30" -> views.
std::vector<ViewSpec> parse_views(const std::string& list) {
    std::vector<ViewSpec> out;
    std::stringstream ss(list);
    std::string item;
    static const std::regex azel(R"(az(-?[0-9]+(?:\.[0-9]+)?)(?:el(-?[0-9]+(?:\.[0-9]+)?))?)");
    while (std::getline(ss, item, ',')) {
        if (item.empty()) continue;
        ViewSpec v;
        v.name = item;
        std::smatch m;
        if (auto c = Camera::named(item)) {
            v.dir = *c;
            v.named = true;
        } else if (std::regex_match(item, m, azel)) {
            v.az = std::stod(m[1].str());
            v.el = m[2].matched ? std::stod(m[2].str()) : 0.0;
            if (v.el < -90 || v.el > 90) throw Error("--views: elevation of \"" + item + "\" must be in [-90, 90]");
            v.dir = Camera::from_azimuth_elevation(v.az, v.el);
        } else {
            throw Error("--views: \"" + item + "\" is neither a view name (front, back, right, left, top, bottom) nor azAelE "
                        "(e.g. az45el30)");
        }
        for (const auto& o : out)
            if (o.name == item) throw Error("--views: \"" + item + "\" is listed twice");
        out.push_back(v);
    }
    if (out.empty()) throw Error("--views is empty");
    return out;
}

std::string number_text(double v) {
    std::ostringstream os;
    os << std::setprecision(10) << v;
    return os.str();
}

// The shortest text that reads back as the same double.
std::string exact_text(double v) {
    if (v == 0) v = 0;   // no "-0"
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

void write_image_atomic(const Image& img, const fs::path& file) {
    FileCommit files;
    write_image(img, files.stage(file));
    files.commit();
}

// Prints what a tool's stage says: warnings unless quiet, notes when verbose.
class ToolMessages : public ProgressSink {
public:
    explicit ToolMessages(const GlobalOptions& g) : g_(g) {}
    void started(const std::string&, const std::string&) override {}
    void progress(const std::string&, double, const std::string&) override {}
    void finished(const std::string&, double) override {}
    void message(const std::string&, const std::string& level, const std::string& text) override {
        if (g_.quiet) return;
        if (level == "warning") print_warning(text);
        else if (g_.verbose) std::cerr << "conceptmesh: " << text << "\n";
    }

private:
    const GlobalOptions& g_;
};

// The views as views.load loads them in a pipeline, run through the registry.
std::shared_ptr<const Views> load_for_tool(const std::string& manifest, const GlobalOptions& g) {
    ToolMessages messages(g);
    StageRunOptions opt;
    opt.sink = &messages;
    opt.node = "views";
    StageRun run = run_stage(Registry::global(), "views.load", text_params({{"manifest", manifest}}), Inputs{}, opt);
    return std::get<std::shared_ptr<const Views>>(run.output);
}

Inputs mesh_and_views(Mesh mesh, std::shared_ptr<const Views> views) {
    Inputs in;
    in.set("mesh", std::shared_ptr<const Mesh>(std::make_shared<Mesh>(std::move(mesh))));
    in.set("views", std::move(views));
    return in;
}

// Views of the mesh itself, framed as render-views frames them: art drawings as the
// images, the pixel-centre masks as the silhouettes.
Views self_views(const Mesh& mesh, const std::vector<ViewSpec>& specs, int size) {
    Vec3f lo, hi;
    mesh.bounds(lo, hi);
    Views views;
    for (const auto& s : specs) {
        View v;
        v.name = s.name;
        v.width = v.height = size;
        v.camera = framed_camera(s.dir, Vec3d(lo), Vec3d(hi), size, size);
        v.image = render_art(mesh, v.camera, size, size);
        const auto m = render_mask(mesh, v.camera, size, size);
        v.coverage.assign(m.begin(), m.end());
        views.views.push_back(std::move(v));
    }
    return views;
}

} // namespace

void add_tool_commands(CLI::App& app, GlobalOptions& g, std::function<int()>& action) {
    // render-views
    {
        auto* cmd = app.add_subcommand("render-views", "Render a mesh from named or azimuth/elevation views into images and a views.yaml manifest");
        struct Opts {
            std::string mesh, out, views = "front,right,top", style = "art", up = "+Y", front = "+Z";
            int size = 1024;
            unsigned seed = 1;
        };
        auto o = std::make_shared<Opts>();
        cmd->add_option("mesh", o->mesh, "Mesh file (.obj .ply .stl .off)")->required();
        cmd->add_option("-o,--output", o->out, "Output folder (created if missing)")->required();
        cmd->add_option("--views", o->views, "Comma-separated views: front back right left top bottom, or azAelE (az45el30)")
            ->capture_default_str();
        cmd->add_option("--size", o->size, "Image width and height in pixels")->capture_default_str()->check(CLI::Range(16, 16384));
        cmd->add_option("--style", o->style, "mask: binary silhouettes; art: shaded drawing with outlines on paper")
            ->capture_default_str()
            ->check(CLI::IsMember({"mask", "art"}));
        cmd->add_option("--up", o->up, "The model's own up axis (+X -X +Y -Y +Z -Z)")->capture_default_str();
        cmd->add_option("--front", o->front, "The model's own front axis (the way it faces)")->capture_default_str();
        cmd->add_option("--seed", o->seed, "Paper grain pattern (art style)")->capture_default_str();
        cmd->add_flag("-q,--quiet", g.quiet, "Only errors and warnings");
        cmd->callback([&g, &action, o] {
            action = [&g, o]() -> int {
                const Orientation orient = parse_orientation(o->up, o->front);
                const std::vector<ViewSpec> specs = parse_views(o->views);
                const Mesh mesh = load_oriented(o->mesh, orient);
                Vec3f lo, hi;
                mesh.bounds(lo, hi);
                // The manifest's world is the output frame: the rotated mesh moved so that the
                // bottom centre of its bounding box is the origin, in the mesh's units.
                const Vec3d pivot{0.5 * (double(lo.x) + double(hi.x)), double(lo.y), 0.5 * (double(lo.z) + double(hi.z))};
                const Vec3d box_lo = Vec3d(lo) - pivot, box_hi = Vec3d(hi) - pivot;
                const Vec3d box_mid{0, 0.5 * (double(hi.y) - double(lo.y)), 0};
                const fs::path dir = o->out;
                std::error_code ec;
                fs::create_directories(dir, ec);
                if (!fs::is_directory(dir)) throw Error("cannot create output folder \"" + dir.string() + "\"");
                std::ostringstream yaml;
                yaml << "# Written by conceptmesh render-views from " << fs::path(o->mesh).filename().string() << " (style "
                     << o->style << ", " << o->size << " px, up " << o->up << ", front " << o->front << ").\n"
                     << "# Framing: bounding-box centre at the image centre, 0.9 * size / largest extent px per unit.\n"
                     << "# The cameras are exact: per view, scale (px per world unit) and origin (image point of the\n"
                     << "# world origin). The world is Y up, front +Z, origin at the bottom centre of the model's\n"
                     << "# bounding box, in the model's units; bounds is that box. Delete scale, origin and bounds to\n"
                     << "# have views.load align the views from their silhouettes instead, as it does for drawings.\n"
                     << "bounds: [" << exact_text(box_lo.x) << ", " << exact_text(box_lo.y) << ", " << exact_text(box_lo.z) << ", "
                     << exact_text(box_hi.x) << ", " << exact_text(box_hi.y) << ", " << exact_text(box_hi.z) << "]\n"
                     << "views:\n";
                ArtOptions art;
                art.seed = o->seed;
                for (const auto& s : specs) {
                    const Camera cam = framed_camera(s.dir, Vec3d(lo), Vec3d(hi), o->size, o->size);
                    Image img;
                    if (o->style == "mask") {
                        const auto m = render_mask(mesh, cam, o->size, o->size);
                        img.width = img.height = o->size;
                        img.channels = 1;
                        img.pixels.assign(m.begin(), m.end());
                    } else {
                        img = render_art(mesh, cam, o->size, o->size, art);
                        // Drop the (opaque) alpha: a drawing on paper.
                        Image rgb;
                        rgb.width = img.width;
                        rgb.height = img.height;
                        rgb.channels = 3;
                        rgb.pixels.resize(std::size_t(img.width) * img.height * 3);
                        for (std::size_t i = 0; i < std::size_t(img.width) * img.height; ++i)
                            for (int k = 0; k < 3; ++k) rgb.pixels[i * 3 + std::size_t(k)] = img.pixels[i * 4 + std::size_t(k)];
                        img = std::move(rgb);
                    }
                    // An object cut by the image border cannot be extracted faithfully.
                    const auto m = render_mask(mesh, cam, o->size, o->size);
                    bool touches = false;
                    for (int i = 0; i < o->size && !touches; ++i)
                        touches = m[std::size_t(i)] || m[std::size_t(o->size - 1) * o->size + i] ||
                                  m[std::size_t(i) * o->size] || m[std::size_t(i) * o->size + o->size - 1];
                    if (touches && !g.quiet)
                        print_warning("view \"" + s.name + "\": the object reaches the image border (the framing fits the "
                                      "bounding box's largest extent, which an oblique view can exceed)");
                    const fs::path file = dir / (s.name + ".png");
                    write_image_atomic(img, file);
                    // The same camera in the world frame: the box's centre, (0, height / 2, 0) there,
                    // at the image centre.
                    const double cx = 0.5 * o->size - cam.scale * dot(box_mid, cam.r);
                    const double cy = 0.5 * o->size + cam.scale * dot(box_mid, cam.u);
                    yaml << "  " << s.name << ": {image: " << file.filename().string();
                    if (!s.named) yaml << ", azimuth: " << number_text(s.az) << ", elevation: " << number_text(s.el);
                    yaml << ", scale: " << exact_text(cam.scale) << ", origin: [" << exact_text(cx) << ", " << exact_text(cy)
                         << "]}\n";
                    if (!g.quiet) std::cerr << "conceptmesh: wrote " << file.string() << "\n";
                }
                const fs::path manifest = dir / "views.yaml";
                {
                    std::ofstream out(dir / "views.yaml.part");
                    out << yaml.str();
                    if (!out.flush()) throw Error("cannot write \"" + manifest.string() + "\"");
                }
                fs::rename(dir / "views.yaml.part", manifest);
                if (!g.quiet) std::cerr << "conceptmesh: wrote " << manifest.string() << "\n";
                return 0;
            };
        });
    }
    // compare
    {
        auto* cmd = app.add_subcommand("compare", "Silhouette error of a mesh against the views of a manifest (xor_pct and IoU)");
        struct Opts {
            std::string mesh, manifest, fit = "none", up = "+Y", front = "+Z";
            bool json = false;
        };
        auto o = std::make_shared<Opts>();
        cmd->add_option("mesh", o->mesh, "Mesh file (.obj .ply .stl .off)")->required();
        cmd->add_option("views", o->manifest, "Views manifest (YAML), loaded as views.load loads it")->required();
        cmd->add_flag("--json", o->json, "Print a JSON object (top-level xor_pct, mean_iou, views)");
        cmd->add_option("--fit", o->fit,
                        "bbox: first map the mesh's bounding box onto the box the aligned views imply; pivot: move the "
                        "mesh so its box's bottom centre is at the origin, keeping its size")
            ->capture_default_str()
            ->check(CLI::IsMember({"none", "bbox", "pivot"}));
        cmd->add_option("--up", o->up, "The mesh's own up axis")->capture_default_str();
        cmd->add_option("--front", o->front, "The mesh's own front axis")->capture_default_str();
        cmd->add_flag("-q,--quiet", g.quiet, "No warnings from loading the views");
        cmd->add_flag("-v,--verbose", g.verbose, "Also say what loading the views dropped or filled");
        cmd->callback([&g, &action, o] {
            action = [&g, o]() -> int {
                const Orientation orient = parse_orientation(o->up, o->front);
                Mesh mesh = load_oriented(o->mesh, orient);
                const auto views = load_for_tool(o->manifest, g);
                fit_mesh(mesh, *views, o->fit);
                const StageRun run = run_stage(Registry::global(), "eval.silhouette_error", {},
                                               mesh_and_views(std::move(mesh), views));
                const json report = json::parse(std::get<std::shared_ptr<const Report>>(run.output)->json);
                if (o->json) {
                    json j;
                    j["xor_pct"] = report["xor_pct"];
                    j["mean_iou"] = report["mean_iou"];
                    j["fit"] = o->fit;
                    j["mesh"] = o->mesh;
                    j["views_manifest"] = o->manifest;
                    j["views"] = report["views"];
                    std::cout << j.dump(2) << "\n";
                    return 0;
                }
                struct Row {
                    std::string view;
                    double input_px, render_px, xor_px, xor_pct, iou;
                };
                std::vector<Row> rows;
                for (const auto& v : report["views"])
                    rows.push_back({v["view"], v["input_px"], v["render_px"], v["xor_px"], v["xor_pct"], v["iou"]});
                struct {
                    std::vector<Row> views;
                    double xor_pct, mean_iou;
                } e{rows, report["xor_pct"], report["mean_iou"]};
                std::cout << std::left << std::setw(14) << "view" << std::right << std::setw(12) << "input px" << std::setw(12)
                          << "mesh px" << std::setw(10) << "xor px" << std::setw(10) << "xor %" << std::setw(9) << "IoU" << "\n";
                for (const auto& v : e.views)
                    std::cout << std::left << std::setw(14) << v.view << std::right << std::fixed << std::setprecision(0)
                              << std::setw(12) << v.input_px << std::setw(12) << v.render_px << std::setw(10) << v.xor_px
                              << std::setprecision(3) << std::setw(10) << v.xor_pct << std::setprecision(4) << std::setw(9)
                              << v.iou << "\n";
                std::cout << std::left << std::setw(14) << "all" << std::right << std::setw(44) << std::setprecision(3)
                          << e.xor_pct << std::setprecision(4) << std::setw(9) << e.mean_iou << "\n"
                          << "xor % = 100 |input xor mesh| / |input| (all: summed over views); IoU per view, all: mean\n";
                return 0;
            };
        });
    }
    // preview
    {
        auto* cmd = app.add_subcommand("preview", "Contact sheet: per view the input drawing, the mesh, and an overlay of the silhouettes");
        struct Opts {
            std::string mesh, manifest, out, fit = "none", up = "+Y", front = "+Z", views = "front,right,top";
            int panel = 320;
        };
        auto o = std::make_shared<Opts>();
        cmd->add_option("mesh", o->mesh, "Mesh file (.obj .ply .stl .off)")->required();
        cmd->add_option("-o,--output", o->out, "Sheet image (.png)")->required();
        cmd->add_option("--views", o->manifest,
                        "Views manifest (YAML); without it the mesh is drawn from front, right and top against itself");
        cmd->add_option("--fit", o->fit,
                        "bbox: map the mesh's bounding box onto the box the aligned views imply; pivot: move the mesh so "
                        "its box's bottom centre is at the origin, keeping its size")
            ->capture_default_str()
            ->check(CLI::IsMember({"none", "bbox", "pivot"}));
        cmd->add_option("--up", o->up, "The mesh's own up axis")->capture_default_str();
        cmd->add_option("--front", o->front, "The mesh's own front axis")->capture_default_str();
        cmd->add_option("--panel", o->panel, "Panel size in pixels")->capture_default_str()->check(CLI::Range(32, 4096));
        cmd->add_flag("-q,--quiet", g.quiet, "Only errors");
        cmd->callback([&g, &action, o] {
            action = [&g, o]() -> int {
                const Orientation orient = parse_orientation(o->up, o->front);
                Mesh mesh = load_oriented(o->mesh, orient);
                std::shared_ptr<const Views> views;
                if (o->manifest.empty()) {
                    views = std::make_shared<Views>(
                        self_views(mesh, parse_views(o->views), std::clamp(2 * o->panel, 128, 1024)));
                } else {
                    views = load_for_tool(o->manifest, g);
                    fit_mesh(mesh, *views, o->fit);
                }
                const std::string title = fs::path(o->mesh).filename().string() +
                                          (o->manifest.empty() ? std::string() : " / " + fs::path(o->manifest).filename().string());
                const StageRun run = run_stage(
                    Registry::global(), "eval.preview",
                    text_params({{"path", o->out}, {"panel", std::to_string(o->panel)}, {"title", title}}),
                    mesh_and_views(std::move(mesh), views));
                if (!g.quiet)
                    std::cerr << "conceptmesh: wrote " << o->out << " (xor " << std::fixed << std::setprecision(3)
                              << json::parse(run.metrics_json.at("xor_pct")).get<double>() << "%, mean IoU "
                              << std::setprecision(4) << json::parse(run.metrics_json.at("mean_iou")).get<double>() << ")\n";
                return 0;
            };
        });
    }
}

} // namespace cm::cli
