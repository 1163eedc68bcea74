// views_iou A.yaml B.yaml: loads two manifests with views.load's code and prints, per view
// key present in both, the IoU of the extracted silhouettes (coverage >= 0.5). Used to check
// that silhouettes extracted from drawings match those extracted from binary masks.
#include <cstdio>
#include <exception>
#include <map>

#include "load.h"

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: views_iou A.yaml B.yaml\n");
        return 2;
    }
    try {
        const cm::Views a = cm::load_views(argv[1], {}).value;
        const cm::Views b = cm::load_views(argv[2], {}).value;
        std::map<std::string, const cm::View*> bv;
        for (const auto& v : b.views) bv[v.name] = &v;
        double worst = 1.0;
        for (const auto& v : a.views) {
            auto it = bv.find(v.name);
            if (it == bv.end() || it->second->coverage.size() != v.coverage.size()) continue;
            std::size_t inter = 0, uni = 0;
            for (std::size_t i = 0; i < v.coverage.size(); ++i) {
                const bool s = v.coverage[i] >= 0.5f, t = it->second->coverage[i] >= 0.5f;
                inter += s && t;
                uni += s || t;
            }
            const double iou = uni ? double(inter) / double(uni) : 1.0;
            worst = std::min(worst, iou);
            std::printf("%-12s iou %.5f  (%zu px differ)\n", v.name.c_str(), iou, uni - inter);
        }
        std::printf("worst        iou %.5f\n", worst);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "views_iou: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
