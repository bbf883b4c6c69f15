# Installs the VTK layer's components into a fresh prefix (a ctest fixture).
#   cmake -DBUILD_DIR=<build> -DPREFIX=<prefix> -DCOMPONENTS=a:b:c -P install_components.cmake
# Only these components are installed so that the test does not depend on targets outside the
# VTK layer having been built.
foreach (var IN ITEMS BUILD_DIR PREFIX COMPONENTS)
  if (NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "install_components.cmake: ${var} is not set")
  endif ()
endforeach ()
file(REMOVE_RECURSE "${PREFIX}") # nothing from an earlier run may make the test pass
string(REPLACE ":" ";" COMPONENTS "${COMPONENTS}")
foreach (component IN LISTS COMPONENTS)
  execute_process(
    COMMAND "${CMAKE_COMMAND}" --install "${BUILD_DIR}" --prefix "${PREFIX}"
            --component "${component}"
    RESULT_VARIABLE rc)
  if (NOT rc EQUAL 0)
    message(FATAL_ERROR "installing component ${component} into ${PREFIX} failed (${rc})")
  endif ()
endforeach ()
