// The hull family: the stages libcm_hull.so provides.
#include "plugins/plugin_abi.h"

namespace cm {
Stage* make_hull_carve();
Stage* make_hull_marching_intersections();
} // namespace cm

CONCEPTMESH_DEFINE_PLUGIN("hull", {"hull.carve", &cm::make_hull_carve},
                          {"hull.marching_intersections", &cm::make_hull_marching_intersections})
