#include "multiview.h"

#include <array>
#include <cstdio>
#include <fstream>
#include <set>

#include "core/error.h"
#include "io/manifest.h"

namespace fs = std::filesystem;

namespace cm::test {

void write_tum_bunny_manifest(const fs::path& dir, const fs::path& manifest) {
    Manifest m;
    m.comment = "TUM bunny (Kolev, Klodt, Brox, Cremers, IJCV 2009): binary silhouettes, object black on white.";
    // The data set's approximate box (its README); every camera sees it whole.
    m.bounds = {-7.5, -10, -7.5, 7.5, 10, 15};
    for (int i = 0; i < 36; i += 2) {
        char name[8];
        std::snprintf(name, sizeof name, "%04d", i);
        const fs::path calib = dir / "calib" / (std::string(name) + ".txt");
        std::ifstream in(calib);
        if (!in) throw Error("cannot read \"" + calib.string() + "\"");
        std::string word;
        in >> word; // CONTOUR
        std::array<double, 12> P{};
        for (double& v : P)
            if (!(in >> v)) throw Error("\"" + calib.string() + "\": expected a 3x4 matrix after CONTOUR");
        ManifestView v;
        v.key = "v" + std::string(name);
        v.image = fs::absolute(dir / "silhouettes" / (std::string(name) + ".pgm"));
        v.background = "white";
        v.matrix = P;
        m.views.push_back(std::move(v));
    }
    write_manifest(manifest, m);
}

void write_dino_manifest(const fs::path& dir, const fs::path& manifest) {
    std::ifstream in(dir / "dinoSR_par.txt");
    if (!in) throw Error("cannot read \"" + (dir / "dinoSR_par.txt").string() + "\"");
    std::set<std::string> good;
    {
        std::ifstream g(dir / "dinoSR_good_silhouette_images.txt");
        std::string f;
        while (g >> f) good.insert(f);
    }
    int count = 0;
    in >> count;
    Manifest m;
    m.comment = "Middlebury dinoSparseRing (Seitz et al., CVPR 2006): white plaster on black.";
    m.bounds = {-0.061897, -0.018874, -0.057845, 0.010897, 0.068227, 0.015495};
    for (int v = 0; v < count; ++v) {
        std::string file;
        double K[9], R[9], t[3];
        in >> file;
        for (double& x : K) in >> x;
        for (double& x : R) in >> x;
        for (double& x : t) in >> x;
        if (!in)
            throw Error("\"" + (dir / "dinoSR_par.txt").string() + "\": short line for view " + std::to_string(v + 1));
        if (!good.empty() && !good.count(file)) continue;
        // P = K [R | t]
        std::array<double, 12> P{};
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c)
                P[4 * r + c] = K[3 * r] * R[c] + K[3 * r + 1] * R[3 + c] + K[3 * r + 2] * R[6 + c];
            P[4 * r + 3] = K[3 * r] * t[0] + K[3 * r + 1] * t[1] + K[3 * r + 2] * t[2];
        }
        ManifestView mv;
        mv.key = fs::path(file).stem().string();
        mv.image = fs::absolute(dir / file);
        mv.background = "black";
        mv.threshold = 0.19;
        mv.matrix = P;
        m.views.push_back(std::move(mv));
    }
    write_manifest(manifest, m);
}

} // namespace cm::test
