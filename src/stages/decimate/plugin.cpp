// The decimate family: the stages libcm_decimate.so provides.
#include "plugins/plugin_abi.h"

namespace cm {
Stage* make_mesh_reduce();
Stage* make_mesh_quadric_decimate();
} // namespace cm

CONCEPTMESH_DEFINE_PLUGIN("decimate", {"mesh.reduce", &cm::make_mesh_reduce},
                          {"mesh.quadric_decimate", &cm::make_mesh_quadric_decimate})
