#include "plugins/plugin_abi.h"

namespace cm {
Stage* make_volume_write();
}

CONCEPTMESH_DEFINE_PLUGIN("volume_write", {"volume.write", &cm::make_volume_write})
