#include "plugins/plugin_abi.h"

namespace cm {
Stage* make_mesh_write();
}

CONCEPTMESH_DEFINE_PLUGIN("mesh_write", {"mesh.write", &cm::make_mesh_write})
