// The write family: the stages libcm_write.so provides.
#include "plugins/plugin_abi.h"

namespace cm {
Stage* make_mesh_write();
Stage* make_volume_write();
} // namespace cm

CONCEPTMESH_DEFINE_PLUGIN("write", {"mesh.write", &cm::make_mesh_write}, {"volume.write", &cm::make_volume_write})
