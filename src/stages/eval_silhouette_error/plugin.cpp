#include "plugins/plugin_abi.h"

namespace cm {
Stage* make_eval_silhouette_error();
}

CONCEPTMESH_DEFINE_PLUGIN("eval_silhouette_error", {"eval.silhouette_error", &cm::make_eval_silhouette_error})
