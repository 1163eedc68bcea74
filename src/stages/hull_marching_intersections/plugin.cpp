#include "plugins/plugin_abi.h"

namespace cm {
Stage* make_hull_marching_intersections();
}

CONCEPTMESH_DEFINE_PLUGIN("hull_marching_intersections",
                          {"hull.marching_intersections", &cm::make_hull_marching_intersections})
