# cmake -DEXE=<the conceptmesh command> -DWORK=<scratch folder> -P check_lazy_plugins.cmake
#
# Plugins load when one of their stages is first used (plugins/registry.h): `conceptmesh
# preview`, which uses views.load and eval.preview, loads those two plugins and never
# OpenVDB; listing the stages loads every plugin, OpenVDB with them (so the check below
# can see a load at all).
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
# A closed tetrahedron.
file(WRITE ${WORK}/tet.obj "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
function(loaded_files out)
  execute_process(COMMAND ${CMAKE_COMMAND} -E env LD_DEBUG=files ${ARGN}
                  OUTPUT_QUIET ERROR_VARIABLE log RESULT_VARIABLE rc WORKING_DIRECTORY ${WORK})
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${ARGN} failed (${rc}):\n${log}")
  endif()
  set(${out} "${log}" PARENT_SCOPE)
endfunction()
loaded_files(all ${EXE} stages)
if(NOT all MATCHES "libopenvdb" OR NOT all MATCHES "libcm_hull")
  message(FATAL_ERROR "`conceptmesh stages` loaded no OpenVDB plugin; this check looks at nothing")
endif()
loaded_files(preview ${EXE} preview tet.obj -o sheet.png -q)
if(NOT EXISTS ${WORK}/sheet.png)
  message(FATAL_ERROR "`conceptmesh preview` wrote no sheet")
endif()
if(NOT preview MATCHES "libcm_eval")
  message(FATAL_ERROR "`conceptmesh preview` did not load libcm_eval.so")
endif()
foreach(lib libopenvdb libcm_hull libcm_extract libcm_write libcm_decimate)
  if(preview MATCHES "${lib}")
    message(FATAL_ERROR "`conceptmesh preview` loaded ${lib}, which it does not use")
  endif()
endforeach()
