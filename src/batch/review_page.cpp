// The review page: index.html with three.js beside it and each model embedded as a data
// URI, so it opens from disk.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <sstream>

#include <nlohmann/json.hpp>

#include "batch/batch.h"
#include "core/data.h"
#include "core/error.h"
#include "io/file_commit.h"
#include "io/manifest.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace cm::batch {

namespace {

std::string base64(const std::string& in) {
    static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((in.size() + 2) / 3 * 4);
    std::size_t i = 0;
    for (; i + 2 < in.size(); i += 3) {
        const unsigned v = (unsigned char)in[i] << 16 | (unsigned char)in[i + 1] << 8 | (unsigned char)in[i + 2];
        for (int s = 18; s >= 0; s -= 6) out += t[(v >> s) & 63];
    }
    if (i < in.size()) {
        unsigned v = (unsigned char)in[i] << 16;
        if (i + 1 < in.size()) v |= (unsigned char)in[i + 1] << 8;
        out += t[(v >> 18) & 63];
        out += t[(v >> 12) & 63];
        out += i + 1 < in.size() ? t[(v >> 6) & 63] : '=';
        out += '=';
    }
    return out;
}

std::string html(const std::string& s) {
    std::string o;
    for (char c : s) {
        switch (c) {
        case '<': o += "&lt;"; break;
        case '>': o += "&gt;"; break;
        case '&': o += "&amp;"; break;
        case '"': o += "&quot;"; break;
        case '\'': o += "&#39;"; break;
        default: o += c;
        }
    }
    return o;
}

// A relative URL from the page to a file under its folder: each part percent-encoded.
std::string url(const fs::path& rel) {
    std::string o;
    for (const auto& part : rel) {
        if (!o.empty()) o += '/';
        for (unsigned char c : part.string()) {
            if (std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == '~') {
                o += char(c);
            } else {
                char b[4];
                std::snprintf(b, sizeof b, "%%%02X", c);
                o += b;
            }
        }
    }
    return o;
}

// The input drawings of an asset, copied beside its results so the page travels with them.
std::vector<fs::path> copy_inputs(const AssetPlan& p) {
    std::vector<fs::path> out;
    try {
        const Manifest m = read_manifest(p.manifest);
        const fs::path dir = p.dir / "inputs";
        fs::create_directories(dir);
        for (const auto& v : m.views) {
            const fs::path to = dir / v.image.filename();
            if (std::find(out.begin(), out.end(), to) != out.end()) continue;
            fs::copy_file(v.image, to, fs::copy_options::overwrite_existing);
            out.push_back(to);
        }
    } catch (const std::exception&) {
        // An unreadable manifest is the asset's failure; its card says so.
    }
    return out;
}

constexpr std::size_t kEagerModels = 12;

// The page draws glTF binaries: the three.js Debian packages (r111), which it copies beside
// itself, has no USD loader, so a .usdz asset gets its link and its preview sheet but no 3D
// view.
bool drawn_here(const std::string& mesh_file) { return lower_extension(mesh_file) == ".glb"; }
const char* kNotDrawn =
    "no 3D view of a .usdz on this page (Debian's three.js reads no USD): open the mesh in a USD viewer";

const char* kPageHead = R"(<!doctype html>
<html lang="en"><head><meta charset="utf-8">
<script>
// Every error on the page, a script that cannot load included, is kept: tests read it.
window.CM_ERRORS = [];
window.addEventListener('error', function (e) {
  var what = e.message || ('cannot load ' + ((e.target && (e.target.src || e.target.href)) || 'a resource'));
  window.CM_ERRORS.push(what);
  document.documentElement.setAttribute('data-errors', String(window.CM_ERRORS.length));
}, true);
// Each model.js hands its model over here, as a data URI.
window.CM_MODELS = {};
window.CM_MODEL = function (name, uri) { window.CM_MODELS[name] = uri; };
</script>
<style>
body { font: 14px system-ui, sans-serif; margin: 16px; background: #f4f4f1; color: #222; }
header { display: flex; gap: 16px; align-items: baseline; flex-wrap: wrap; }
h1 { font-size: 20px; margin: 0 0 8px 0; }
.cards { display: flex; flex-wrap: wrap; gap: 12px; }
.card { background: #fff; border: 1px solid #ccc; border-radius: 6px; padding: 10px; width: 560px; box-sizing: border-box; }
.card.failed { border-color: #c33; }
.card h2 { font-size: 16px; margin: 0 0 6px 0; }
.badge { font-size: 12px; padding: 1px 6px; border-radius: 3px; background: #dfe; }
.failed .badge { background: #fdd; } .skipped .badge { background: #eef; }
.cause { color: #a00; font-family: monospace; white-space: pre-wrap; }
.row { display: flex; gap: 8px; align-items: flex-start; }
canvas.view3d { width: 320px; height: 240px; background: #2a2f38; border-radius: 4px; }
.no3d { width: 320px; color: #666; font-size: 13px; }
.inputs img { height: 72px; border: 1px solid #ddd; margin: 0 4px 4px 0; background: #fff; }
.preview img { max-width: 100%; max-height: 200px; margin-top: 6px; }
table.fig { border-collapse: collapse; font-size: 13px; }
table.fig td { padding: 1px 6px 1px 0; } table.fig td:first-child { color: #666; }
</style>
)";

const char* kPageScript = R"(
<script>
(function () {
  var models = window.CM_MODELS;
  function buffer(uri) {
    var b = atob(uri.slice(uri.indexOf(',') + 1)), a = new Uint8Array(b.length);
    for (var i = 0; i < b.length; ++i) a[i] = b.charCodeAt(i);
    return a.buffer;
  }
  function fail(card, what) {
    window.CM_ERRORS.push(card.dataset.name + ': ' + what);
    document.documentElement.setAttribute('data-errors', String(window.CM_ERRORS.length));
  }
  function show(card) {
    var canvas = card.querySelector('canvas.view3d'), name = card.dataset.name;
    var renderer = new THREE.WebGLRenderer({ canvas: canvas, antialias: true, preserveDrawingBuffer: true });
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    renderer.setSize(canvas.clientWidth, canvas.clientHeight, false);
    renderer.setClearColor(0x2a2f38);
    var scene = new THREE.Scene();
    scene.add(new THREE.HemisphereLight(0xffffff, 0x444455, 0.55));
    var sun = new THREE.DirectionalLight(0xffffff, 0.6);
    sun.position.set(1, 2, 3);
    scene.add(sun);
    var camera = new THREE.PerspectiveCamera(35, canvas.clientWidth / canvas.clientHeight, 0.001, 1e7);
    new THREE.GLTFLoader().parse(buffer(models[name]), '', function (gltf) {
      // glTF's default material is fully metallic, which is black without an environment:
      // a plain clay look shows the shape.
      var clay = new THREE.MeshStandardMaterial({ color: 0x9ea8bc, metalness: 0, roughness: 0.8 });
      gltf.scene.traverse(function (o) {
        if (!o.isMesh) return;
        if (!o.geometry.attributes.normal) o.geometry.computeVertexNormals();
        o.material = clay;
      });
      scene.add(gltf.scene);
      var box = new THREE.Box3().setFromObject(gltf.scene), c = box.getCenter(new THREE.Vector3());
      var r = box.getSize(new THREE.Vector3()).length() / 2 || 1;
      // The three-quarter view the previews use: front-right, a little above.
      camera.position.set(c.x + 1.7 * r, c.y + 1.1 * r, c.z + 2.4 * r);
      camera.near = r / 100; camera.far = r * 100; camera.updateProjectionMatrix();
      var controls = new THREE.OrbitControls(camera, canvas);
      controls.target.copy(c); controls.update();
      function draw() { renderer.render(scene, camera); }
      controls.addEventListener('change', draw);
      draw();
      card.setAttribute('data-drawn', 'yes');
    }, function (e) { fail(card, 'the model cannot be read: ' + (e && e.message || e)); });
  }
  function load(card) {
    if (card.dataset.loading) return;
    card.setAttribute('data-loading', 'yes');
    var s = document.createElement('script');
    s.src = card.dataset.model;
    s.onload = function () { show(card); };
    document.head.appendChild(s);
  }
  // The first models came with the page; the others load when their card comes into view,
  // so that a page of many assets stays light.
  var cards = Array.prototype.slice.call(document.querySelectorAll('.card[data-model]'));
  cards = cards.filter(function (c) {
    if (!models[c.dataset.name]) return true;
    c.setAttribute('data-loading', 'yes');
    show(c);
    return false;
  });
  if ('IntersectionObserver' in window) {
    var seen = new IntersectionObserver(function (entries) {
      entries.forEach(function (e) { if (e.isIntersecting) { seen.unobserve(e.target); load(e.target); } });
    }, { rootMargin: '200px' });
    cards.forEach(function (c) { seen.observe(c); });
  } else {
    cards.forEach(load);
  }
  var keys = { error: function (c) { return -(c.dataset.status === 'failed' ? 1e9 : parseFloat(c.dataset.xor || '-1')); },
               name: function (c) { return c.dataset.name; },
               time: function (c) { return -parseFloat(c.dataset.seconds); },
               faces: function (c) { return -parseFloat(c.dataset.faces || '0'); } };
  document.getElementById('sort').addEventListener('change', function () { sort(this.value); });
  function sort(by) {
    var list = document.getElementById('cards'), all = Array.prototype.slice.call(list.children), k = keys[by];
    all.sort(function (a, b) { var x = k(a), y = k(b); return x < y ? -1 : x > y ? 1 : 0; });
    all.forEach(function (c) { list.appendChild(c); });
  }
  sort('error');
})();
</script>
)";
} // namespace

void write_review_page(const std::vector<AssetPlan>& plans, const std::vector<AssetResult>& results,
                       const fs::path& out_dir, const std::string& title) {
    const char* env = std::getenv("CONCEPTMESH_THREE_JS");
    const fs::path three = env && *env ? fs::path(env) : fs::path("/usr/share/javascript/three");
    const std::vector<std::pair<fs::path, std::string>> scripts = {
        {three / "three.min.js", "three.min.js"},
        {three / "examples/js/loaders/GLTFLoader.js", "GLTFLoader.js"},
        {three / "examples/js/controls/OrbitControls.js", "OrbitControls.js"}};
    for (const auto& [from, to] : scripts)
        if (!fs::is_regular_file(from))
            throw Error("the review page needs three.js: " + from.string() +
                        " is missing (install Debian's libjs-three, or set CONCEPTMESH_THREE_JS to its folder)");
    const fs::path dir = fs::absolute(out_dir);
    fs::create_directories(dir / "three");
    for (const auto& [from, to] : scripts)
        fs::copy_file(from, dir / "three" / to, fs::copy_options::overwrite_existing);

    std::size_t failed = 0;
    for (const auto& r : results) failed += r.status == "failed";
    std::ostringstream h;
    h << kPageHead << "<title>" << html(title) << " - conceptmesh batch</title>\n";
    for (const auto& s : scripts) h << "<script src=\"three/" << s.second << "\"></script>\n";
    h << "</head><body>\n<header><h1>" << html(title) << "</h1><span>" << results.size() << " assets, " << failed
      << " failed</span><label>sort by <select id=\"sort\"><option value=\"error\">error (worst first)</option>"
      << "<option value=\"name\">name</option><option value=\"time\">time</option><option "
         "value=\"faces\">faces</option></select></label></header>\n<div class=\"cards\" id=\"cards\">\n";
    for (std::size_t i = 0; i < results.size(); ++i) {
        const AssetResult& r = results[i];
        const AssetPlan& p = plans[i];
        const fs::path rel = fs::relative(r.dir, dir);
        const bool has_mesh = r.status != "failed" && !p.mesh_file.empty() && fs::is_regular_file(r.dir / p.mesh_file);
        std::string model_attr;
        if (has_mesh && drawn_here(p.mesh_file)) {
            // The model as a data URI in a script of its own: a page opened from disk may not
            // fetch files, but it may run scripts beside it.
            const std::string js = "CM_MODEL(" + json(r.name).dump() + ", \"data:model/gltf-binary;base64," +
                                   base64(read_bytes(r.dir / p.mesh_file)) + "\");\n";
            write_file_atomic(r.dir / "model.js", js);
            model_attr = " data-model=\"" + html(url(rel / "model.js")) + "\"";
        }
        h << "<div class=\"card " << r.status << "\" data-name=\"" << html(r.name) << "\" data-status=\"" << r.status
          << "\" data-seconds=\"" << fixed_digits(r.seconds, 2) << "\"";
        if (r.xor_pct >= 0) h << " data-xor=\"" << r.xor_pct << "\"";
        if (r.faces >= 0) h << " data-faces=\"" << r.faces << "\"";
        h << model_attr << ">\n<h2>" << html(r.name) << " <span class=\"badge\">"
          << (r.status == "skipped" ? "up to date" : r.status) << "</span></h2>\n";
        if (r.status == "failed") h << "<div class=\"cause\">" << html(r.cause) << "</div>\n";
        h << "<div class=\"row\">";
        if (!model_attr.empty()) h << "<canvas class=\"view3d\" width=\"320\" height=\"240\"></canvas>";
        else if (has_mesh) h << "<div class=\"no3d\">" << kNotDrawn << "</div>";
        h << "<div><table class=\"fig\">"
          << "<tr><td>silhouette error</td><td>" << (r.xor_pct >= 0 ? fixed_digits(r.xor_pct, 3) + " %" : "-")
          << "</td></tr>";
        for (const auto& [view, x] : r.view_xor)
            h << "<tr><td>&nbsp;&nbsp;" << html(view) << "</td><td>" << fixed_digits(x, 3) << " %</td></tr>";
        h << "<tr><td>faces</td><td>" << (r.faces >= 0 ? std::to_string(long(r.faces)) : "-") << "</td></tr>"
          << "<tr><td>wall time</td><td>" << fixed_digits(r.seconds, 2) << " s</td></tr>"
          << "<tr><td>peak memory</td><td>" << (r.peak_mib > 0 ? fixed_digits(r.peak_mib, 0) + " MiB" : "-")
          << "</td></tr>"
          << "<tr><td>files</td><td>";
        if (has_mesh) h << "<a href=\"" << html(url(rel / p.mesh_file)) << "\">mesh</a> ";
        h << "<a href=\"" << html(url(rel / "log.txt")) << "\">log</a> <a href=\"" << html(url(rel / "run.json"))
          << "\">report</a></td></tr></table>\n<div class=\"inputs\">";
        for (const auto& in : copy_inputs(p))
            h << "<img src=\"" << html(url(fs::relative(in, dir))) << "\" alt=\"" << html(in.filename().string())
              << "\" title=\"" << html(in.filename().string()) << "\">";
        h << "</div></div></div>\n";
        if (r.status != "failed" && !p.preview_file.empty() && fs::is_regular_file(r.dir / p.preview_file))
            h << "<div class=\"preview\"><a href=\"" << html(url(rel / p.preview_file)) << "\"><img src=\""
              << html(url(rel / p.preview_file)) << "\" alt=\"preview sheet\"></a></div>\n";
        h << "</div>\n";
    }
    h << "</div>\n";
    // The first models load with the page itself (no wait for a card to scroll into view).
    std::size_t eager = 0;
    for (std::size_t i = 0; i < results.size() && eager < kEagerModels; ++i)
        if (fs::is_regular_file(results[i].dir / "model.js") && results[i].status != "failed" &&
            drawn_here(plans[i].mesh_file)) {
            h << "<script src=\"" << html(url(fs::relative(results[i].dir / "model.js", dir))) << "\"></script>\n";
            ++eager;
        }
    h << kPageScript << "</body></html>\n";
    write_file_atomic(dir / "index.html", h.str());
}

} // namespace cm::batch
