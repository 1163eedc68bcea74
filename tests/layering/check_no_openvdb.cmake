# cmake -DEXE=<the conceptmesh command> -P check_no_openvdb.cmake
#
# The command, with every library it loads at start (libconceptmesh_geometry among them),
# loads no OpenVDB: binding OpenVDB's symbols costs about 60 ms before main, which only the
# plugins that use OpenVDB (hull, extract, write) should pay, when they are loaded.
execute_process(COMMAND ldd ${EXE} OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "ldd ${EXE} failed: ${err}")
endif()
if(NOT out MATCHES "libconceptmesh_geometry")
  message(FATAL_ERROR "${EXE} does not load libconceptmesh_geometry at start; this check looks at nothing:\n${out}")
endif()
if(out MATCHES "libopenvdb")
  message(FATAL_ERROR "${EXE} loads OpenVDB at start (a library below it links it):\n${out}")
endif()
