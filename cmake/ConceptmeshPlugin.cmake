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

# conceptmesh_add_family(<family> [LIBS <targets...>])
#
# A stage family folder (stages/<family>/) holds plugin.cpp (the
# CONCEPTMESH_DEFINE_PLUGIN entry naming every stage of the family, nothing else)
# and the stages with their algorithms: every other .cpp of the folder is built, so a
# new stage needs no line here. The code becomes an OBJECT library
# cm_<family>_obj that the family's tests link directly; plugin.cpp plus those
# objects become libcm_<family>.so in the plugin folder next to the executable
# (<build>/lib/conceptmesh/plugins), installed to the same relative place.
function(conceptmesh_add_family name)
  cmake_parse_arguments(ARG "" "" "LIBS" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cpp)
  list(REMOVE_ITEM sources ${CMAKE_CURRENT_SOURCE_DIR}/plugin.cpp)
  add_library(cm_${name}_obj OBJECT ${sources})
  target_link_libraries(cm_${name}_obj PUBLIC cm_core ${ARG_LIBS} PRIVATE conceptmesh_warnings)
  target_include_directories(cm_${name}_obj PUBLIC ${CMAKE_CURRENT_SOURCE_DIR})
  add_library(cm_${name} MODULE plugin.cpp)
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
