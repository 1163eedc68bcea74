# conceptmesh_add_plugin(<name> SOURCES <files...> [LIBS <targets...>])
#
# A stage folder holds plugin.cpp (the CONCEPTMESH_DEFINE_PLUGIN entry, nothing
# else) and the stage code. The stage code becomes an OBJECT library
# cm_<name>_obj that tests link directly; plugin.cpp plus those objects become
# libcm_<name>.so in the plugin folder next to the executable
# (<build>/lib/conceptmesh/plugins), installed to the same relative place.
function(conceptmesh_add_plugin name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBS" ${ARGN})
  add_library(cm_${name}_obj OBJECT ${ARG_SOURCES})
  target_link_libraries(cm_${name}_obj PUBLIC conceptmesh ${ARG_LIBS} PRIVATE conceptmesh_warnings)
  target_include_directories(cm_${name}_obj PUBLIC ${CMAKE_CURRENT_SOURCE_DIR})
  add_library(cm_${name} MODULE plugin.cpp)
  target_link_libraries(cm_${name} PRIVATE cm_${name}_obj conceptmesh_warnings)
  set_target_properties(cm_${name} PROPERTIES
    PREFIX "lib"
    LIBRARY_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/${CONCEPTMESH_PLUGIN_SUBDIR}
    CXX_VISIBILITY_PRESET hidden
    INSTALL_RPATH "$ORIGIN/../..")
  install(TARGETS cm_${name} LIBRARY DESTINATION ${CONCEPTMESH_PLUGIN_SUBDIR})
  set_property(GLOBAL APPEND PROPERTY CONCEPTMESH_PLUGINS cm_${name})
endfunction()
