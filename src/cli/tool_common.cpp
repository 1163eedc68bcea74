#include "cli/tool_common.h"

#include <cmath>
#include <iostream>
#include <regex>
#include <sstream>

#include "core/error.h"
#include "io/mesh_io.h"
#include "pipeline/run_stage.h"

namespace cm::cli {

void set_action(CLI::App* cmd, std::function<int()>& action, std::function<int()> run) {
    cmd->callback([&action, run = std::move(run)] { action = run; });
}

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

// Maps the mesh's bounding box onto the box the aligned views imply (per axis).
void fit_bbox(Mesh& m, const Views& views) {
    if (!views.has_bounds)
        throw Error(
            "--fit bbox needs the box the views imply; these calibrated views give no bounds in their manifest");
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

// Moves the mesh so its bounding box's bottom centre is at the origin, keeping its size.
void fit_pivot(Mesh& m) {
    Vec3f lo, hi;
    m.bounds(lo, hi);
    const Vec3d pivot = box_pivot(lo, hi);
    for (auto& p : m.positions) p = Vec3f(Vec3d(p) - pivot);
}

// One item of --views: a view name or azAelE.
ViewSpec parse_view(const std::string& item) {
    static const std::regex azel(R"(az(-?[0-9]+(?:\.[0-9]+)?)(?:el(-?[0-9]+(?:\.[0-9]+)?))?)");
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
        throw Error("--views: \"" + item +
                    "\" is neither a view name (front, back, right, left, top, bottom) nor azAelE "
                    "(e.g. az45el30)");
    }
    return v;
}

} // namespace

void AxisOptions::add_to(CLI::App* cmd, const std::string& up_doc, const std::string& front_doc) {
    cmd->add_option("--up", up, up_doc)->capture_default_str();
    cmd->add_option("--front", front, front_doc)->capture_default_str();
}

Orientation AxisOptions::parse() const {
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

Vec3d box_pivot(const Vec3f& lo, const Vec3f& hi) {
    return {0.5 * (double(lo.x) + double(hi.x)), double(lo.y), 0.5 * (double(lo.z) + double(hi.z))};
}

void add_fit_option(CLI::App* cmd, std::string& fit, const std::string& doc) {
    cmd->add_option("--fit", fit, doc)->capture_default_str()->check(CLI::IsMember({"none", "bbox", "pivot"}));
}

void fit_mesh(Mesh& m, const Views& views, const std::string& fit) {
    if (fit == "bbox") fit_bbox(m, views);
    else if (fit == "pivot") fit_pivot(m);
}

std::vector<ViewSpec> parse_views(const std::string& list) {
    std::vector<ViewSpec> out;
    std::stringstream ss(list);
    std::string item;
    while (std::getline(ss, item, ',')) {
        if (item.empty()) continue;
        ViewSpec v = parse_view(item);
        for (const auto& o : out)
            if (o.name == item) throw Error("--views: \"" + item + "\" is listed twice");
        out.push_back(v);
    }
    if (out.empty()) throw Error("--views is empty");
    return out;
}

void ToolMessages::message(const std::string&, const std::string& level, const std::string& text) {
    if (g_.quiet) return;
    if (level == "warning") print_warning(text);
    else if (g_.verbose) std::cerr << "conceptmesh: " << text << "\n";
}

std::shared_ptr<const Views> load_views_through_registry(const std::string& manifest, const GlobalOptions& g) {
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

Pipeline load_checked(const std::string& file, const std::vector<std::string>& sets, const GlobalOptions& g) {
    Pipeline p = Pipeline::load(file);
    for (const auto& s : sets) p.apply_override(s);
    with_plugin_warnings(g, [&] { p.validate(Registry::global()); });
    return p;
}

} // namespace cm::cli
