#include "plugins/plugin_abi.h"

namespace cm {
Stage* make_eval_preview();
}

CONCEPTMESH_DEFINE_PLUGIN("eval_preview", {"eval.preview", &cm::make_eval_preview})
