# cmake -DDIR=<the build tree> -P check_runpaths.cmake
#
# The command, its libraries and its plugins, as built, look for libraries only where their
# RUNPATH says, relative to themselves: no empty entry, which the dynamic loader reads as the
# current directory (a library of the same name there would be loaded, and every library is
# first looked for there). Checked with readelf; skipped (exit 2) without it.
find_program(READELF readelf)
if(NOT READELF)
  message("readelf not found: skipped")
  cmake_language(EXIT 2)
endif()
file(GLOB_RECURSE files LIST_DIRECTORIES false "${DIR}/bin/conceptmesh" "${DIR}/lib/*.so")
list(LENGTH files n)
if(n LESS 3)
  message(FATAL_ERROR "found ${n} binaries under ${DIR}; this check looks at nothing")
endif()
set(bad "")
foreach(f ${files})
  execute_process(COMMAND ${READELF} -d ${f} OUTPUT_VARIABLE out RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "readelf -d ${f} failed")
  endif()
  string(REGEX MATCH "\\((RUNPATH|RPATH)\\)[^[]*\\[([^]]*)\\]" m "${out}")
  set(path "${CMAKE_MATCH_2}")
  if(NOT path STREQUAL "" AND (path MATCHES "^:" OR path MATCHES ":$" OR path MATCHES "::"))
    string(APPEND bad "\n  ${f}: ${path}")
  endif()
endforeach()
if(NOT bad STREQUAL "")
  message(FATAL_ERROR "RUNPATH with an empty entry (the current directory):${bad}")
endif()
message("${n} binaries, every RUNPATH without an empty entry")
