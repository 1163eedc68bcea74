// multiview_manifests OUT_DIR [SHARED_DATA_DIR]: writes OUT_DIR/tum_bunny.yaml and
// OUT_DIR/dino.yaml, the views manifests of the calibrated photo sets of
// ../shared/data/multiview, for use from the command line. They name the images by
// absolute path (the images are not copied) and are the manifests the tests write
// (tests/stages/hull/multiview.cpp).
#include <cstdio>
#include <exception>
#include <filesystem>

#include "multiview.h"

namespace fs = std::filesystem;

int main(int argc, char** argv) {
    if (argc < 2 || argc > 3) {
        std::fprintf(stderr, "usage: multiview_manifests OUT_DIR [SHARED_DATA_DIR]\n");
        return 2;
    }
    try {
        const fs::path out = argv[1];
        const fs::path data = argc > 2 ? fs::path(argv[2]) : fs::path(CM_SHARED_DIR) / "data";
        fs::create_directories(out);
        cm::test::write_tum_bunny_manifest(data / "multiview" / "tum_bunny", out / "tum_bunny.yaml");
        cm::test::write_dino_manifest(data / "multiview" / "middlebury_dinoSparseRing", out / "dino.yaml");
    } catch (const std::exception& e) {
        std::fprintf(stderr, "multiview_manifests: %s\n", e.what());
        return 1;
    }
    return 0;
}
