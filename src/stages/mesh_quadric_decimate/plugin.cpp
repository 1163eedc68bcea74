#include "plugins/plugin_abi.h"

namespace cm {
Stage* make_mesh_quadric_decimate();
}

CONCEPTMESH_DEFINE_PLUGIN("mesh_quadric_decimate", {"mesh.quadric_decimate", &cm::make_mesh_quadric_decimate})
