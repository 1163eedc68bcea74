# cmake -DROOT=<checkout> -DDOC=<file relative to ROOT> -P check_paths.cmake
#
# Every file or folder of the checkout that DOC names (a path in backquotes starting with
# src/, tests/, bench/, cmake/, schemas/, pipelines/, scripts/, examples/ or docs/) exists:
# a guide to the code that names a file the code no longer has fails here. A name with a
# placeholder (<family>, *) is a pattern, not a file, and is left out; a program is named by
# its source without the ending (`bench/views/sketch_views`).
file(READ "${ROOT}/${DOC}" text)
string(REGEX MATCHALL "`(src|tests|bench|cmake|schemas|pipelines|scripts|examples|docs)/[^` ]*`" names "${text}")
list(REMOVE_DUPLICATES names)
set(bad 0)
set(checked 0)
foreach(n ${names})
  string(REGEX REPLACE "^`(.*)`$" "\\1" path "${n}")
  if(path MATCHES "[<>*{}]")
    continue()
  endif()
  string(REGEX REPLACE "[:,.;]$" "" path "${path}")
  math(EXPR checked "${checked} + 1")
  # A program of bench/ or tests/ is named by its source's name without the ending.
  if(NOT EXISTS "${ROOT}/${path}" AND NOT EXISTS "${ROOT}/${path}.cpp" AND NOT EXISTS "${ROOT}/${path}.sh"
     AND NOT EXISTS "${ROOT}/${path}.py")
    message(SEND_ERROR "${DOC} names `${path}`, which does not exist")
    math(EXPR bad "${bad} + 1")
  endif()
endforeach()
if(bad GREATER 0)
  message(FATAL_ERROR "${bad} of the ${checked} paths ${DOC} names do not exist")
endif()
message(STATUS "${DOC}: the ${checked} paths it names exist")
