# The folder of this file, for the templates the functions below configure.
set(CONCEPTMESH_CMAKE_DIR ${CMAKE_CURRENT_LIST_DIR})

# conceptmesh_no_undefined(<target>)
#
# A shared library or plugin must resolve every symbol against what it links, so a
# layer that calls into a layer above it fails to link. Sanitizer builds leave the
# runtime's symbols to the executable, so the check is off there.
function(conceptmesh_no_undefined target)
  if(NOT CMAKE_CXX_FLAGS MATCHES "sanitize")
    target_link_options(${target} PRIVATE -Wl,--no-undefined)
  endif()
endfunction()

# conceptmesh_add_family(<family> STAGES <stage names...> [LIBS <targets...>])
#
# A stage family folder (stages/<family>/) holds the family's stages with their
# algorithms: every .cpp of the folder is built, so a new source file needs no line
# here. STAGES names every stage the family provides; each "a.b_c" is made by a
# factory `cm::Stage* cm::make_a_b_c()` defined in one of those files. From that list
# the plugin's entry point (CONCEPTMESH_DEFINE_PLUGIN, see plugins/plugin_abi.h) is
# generated into the build tree, so a family has no entry file of its own to copy.
# The code becomes an OBJECT library cm_<family>_obj that the family's tests link
# directly; the entry plus those objects become libcm_<family>.so in the plugin folder
# next to the executable (<build>/lib/conceptmesh/plugins), installed to the same
# relative place.
function(conceptmesh_add_family name)
  cmake_parse_arguments(ARG "" "" "STAGES;LIBS" ${ARGN})
  if(NOT ARG_STAGES)
    message(FATAL_ERROR "conceptmesh_add_family(${name}): name the family's stages after STAGES")
  endif()
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cpp)
  add_library(cm_${name}_obj OBJECT ${sources})
  target_link_libraries(cm_${name}_obj PUBLIC cm_core ${ARG_LIBS} PRIVATE conceptmesh_warnings)
  target_include_directories(cm_${name}_obj PUBLIC ${CMAKE_CURRENT_SOURCE_DIR})

  set(CM_FAMILY ${name})
  set(CM_FACTORY_DECLS "")
  set(CM_FACTORY_ENTRIES "")
  foreach(stage IN LISTS ARG_STAGES)
    string(REPLACE "." "_" factory "make_${stage}")
    string(APPEND CM_FACTORY_DECLS "Stage* ${factory}();\n")
    list(APPEND CM_FACTORY_ENTRIES "{\"${stage}\", &cm::${factory}}")
  endforeach()
  list(JOIN CM_FACTORY_ENTRIES ", " CM_FACTORY_ENTRIES)
  set(entry ${CMAKE_CURRENT_BINARY_DIR}/cm_${name}_plugin.cpp)
  configure_file(${CONCEPTMESH_CMAKE_DIR}/family_plugin.cpp.in ${entry} @ONLY)

  add_library(cm_${name} MODULE ${entry})
  target_link_libraries(cm_${name} PRIVATE cm_${name}_obj cm_plugins conceptmesh_warnings)
  conceptmesh_no_undefined(cm_${name})
  set_target_properties(cm_${name} PROPERTIES
    PREFIX "lib"
    LIBRARY_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/${CONCEPTMESH_PLUGIN_SUBDIR}
    CXX_VISIBILITY_PRESET hidden
    INSTALL_RPATH "$ORIGIN/../..")
  install(TARGETS cm_${name} LIBRARY DESTINATION ${CONCEPTMESH_PLUGIN_SUBDIR})
  set_property(GLOBAL APPEND PROPERTY CONCEPTMESH_PLUGINS cm_${name})
endfunction()
