# Imath, as much of it as conceptmesh links: the Imath::Imath library (OpenVDB's half
# type). Debian's own ImathTargets.cmake also declares the Python bindings, whose
# library ships in another package, and a first configure then prints a long warning
# about a missing libPyImath. Nothing here uses them, so only Imath::Imath is defined.
if(NOT TARGET Imath::Imath)
  find_library(CONCEPTMESH_IMATH_LIBRARY NAMES Imath-3_1 Imath REQUIRED)
  find_path(CONCEPTMESH_IMATH_INCLUDE Imath/half.h REQUIRED)
  add_library(Imath::Imath SHARED IMPORTED)
  set_target_properties(Imath::Imath PROPERTIES
    IMPORTED_LOCATION "${CONCEPTMESH_IMATH_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${CONCEPTMESH_IMATH_INCLUDE};${CONCEPTMESH_IMATH_INCLUDE}/Imath")
endif()
set(Imath_FOUND TRUE)
