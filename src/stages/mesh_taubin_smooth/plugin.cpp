#include "plugins/plugin_abi.h"

namespace cm {
Stage* make_mesh_taubin_smooth();
}

CONCEPTMESH_DEFINE_PLUGIN("mesh_taubin_smooth", {"mesh.taubin_smooth", &cm::make_mesh_taubin_smooth})
