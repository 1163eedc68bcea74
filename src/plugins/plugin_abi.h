// The plugin ABI. A plugin is a shared library with one extern "C" entry
// symbol, `conceptmesh_plugin_entry`, returning a PluginDescriptor. The loader
// checks the plugin ABI and the OpenVDB ABI before touching anything else.
#pragma once
#include <cstddef>
#include <cstdint>

#include <openvdb/version.h>

namespace cm {
class Stage;
}

/// Bumped whenever Stage, the data types or this descriptor change incompatibly.
#define CONCEPTMESH_PLUGIN_ABI_VERSION 4u
#define CONCEPTMESH_PLUGIN_ENTRY conceptmesh_plugin_entry
#define CONCEPTMESH_PLUGIN_ENTRY_NAME "conceptmesh_plugin_entry"

extern "C" {

struct ConceptmeshStageFactory {
    const char* stage_name; ///< "hull.carve"
    cm::Stage* (*create)(); ///< new stage; the host owns it (deletes through ~Stage)
};

struct ConceptmeshPluginDescriptor {
    std::uint32_t plugin_abi;  ///< CONCEPTMESH_PLUGIN_ABI_VERSION when built
    const char* name;          ///< "hull"
    const char* version;       ///< "0.1.0"
    std::uint32_t openvdb_abi; ///< OPENVDB_ABI_VERSION_NUMBER when built
    std::size_t stage_count;
    const ConceptmeshStageFactory* stages;
};

typedef const ConceptmeshPluginDescriptor* (*ConceptmeshPluginEntry)();
}

/// Declares a plugin's entry point. Use once per plugin library:
///   CONCEPTMESH_DEFINE_PLUGIN("hull", {"hull.carve", &make_carve}, {...})
#define CONCEPTMESH_DEFINE_PLUGIN(NAME, ...)                                                                          \
    extern "C" __attribute__((visibility("default"))) const ConceptmeshPluginDescriptor* CONCEPTMESH_PLUGIN_ENTRY() { \
        static const ConceptmeshStageFactory factories[] = {__VA_ARGS__};                                             \
        static const ConceptmeshPluginDescriptor d = {CONCEPTMESH_PLUGIN_ABI_VERSION,                                 \
                                                      NAME,                                                           \
                                                      CONCEPTMESH_VERSION_STRING,                                     \
                                                      OPENVDB_ABI_VERSION_NUMBER,                                     \
                                                      sizeof(factories) / sizeof(factories[0]),                       \
                                                      factories};                                                     \
        return &d;                                                                                                    \
    }
