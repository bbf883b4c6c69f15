# The VTK layer: the module Simpli::Filters (filters/), its Python wrapping (package `simpli`)
# and the ParaView plugin SimpliPlugin (plugin/ + paraview_xml/).
#
# Included from the top-level CMakeLists.txt (so everything defined here is visible in tests/)
# when SIMPLI_WITH_VTK is ON. Recipe: shared/reference/vtk_paraview_build.md.
#
# Variables defined for the tests:
#   SIMPLI_PY_DEST             Python package root, relative to the prefix (lib/python3/dist-packages)
#   SIMPLI_BUILD_PYTHONPATH    that directory in the build tree (empty without Python wrapping)
#   SIMPLI_PYTHON_OK           ON if Python3_EXECUTABLE can import vtkmodules
#   SIMPLI_PLUGIN_DEST         plugin directory relative to the prefix (ParaView builds only)
#   SIMPLI_PVPYTHON, SIMPLI_PVBATCH   ParaView's interpreters (ParaView builds only)
#   SIMPLI_VTK_INSTALL_COMPONENTS     install components that make up the VTK layer

# Install components of the VTK layer, kept apart from the rest of the project so that the
# module, its wrapper and the plugin can be installed (and tested) on their own.
set(SIMPLI_VTK_INSTALL_COMPONENTS simpli_vtk_runtime simpli_vtk_development)

if (SIMPLI_USE_PARAVIEW)
  # Only what a server-side plugin needs: with no COMPONENTS, ParaView's config makes every
  # external dependency it was built with (Qt5 dev, HDF5, GDAL, ...) REQUIRED.
  # The plugin's GUI part (plugin/gui: an MLI shown through its camera, the SIMPLI menu) needs
  # ParaView's Qt client libraries and the Qt5 dev packages their link interface names
  # (qtbase5-dev, libqt5opengl5-dev: VTK::GUISupportQt links Qt5::OpenGL). Linking
  # pqApplicationComponents without them fails at generate time ("Qt5::OpenGL ... target was
  # not found"), so SIMPLI_PARAVIEW_GUI (plugin/, tests/vtk/) is ON only when they are there;
  # otherwise the plugin is server-side only.
  find_package(Qt5 QUIET COMPONENTS Widgets OpenGL)
  find_package(ParaView 5.11 REQUIRED COMPONENTS
    RemotingCore RemotingServerManager RemotingClientServerStream
    OPTIONAL_COMPONENTS pqApplicationComponents)
  set(SIMPLI_PARAVIEW_GUI OFF)
  if (PARAVIEW_USE_QT AND TARGET ParaView::pqApplicationComponents)
    if (Qt5Widgets_FOUND AND Qt5OpenGL_FOUND)
      set(SIMPLI_PARAVIEW_GUI ON)
    else ()
      message(STATUS "simpli: no Qt5 Widgets/OpenGL dev packages (qtbase5-dev, "
                     "libqt5opengl5-dev): the ParaView plugin will have no GUI part")
    endif ()
    # pqApplicationComponents' link interface reaches VTK's imported third-party libraries,
    # whose own interfaces name targets of their -dev packages (HDF5, libxml2, NetCDF, Boost)
    # that the plugin never uses: the shared libraries carry their own dependencies. Empty
    # stand-ins let CMake generate without installing those packages.
    foreach (_simpli_dep IN ITEMS hdf5::hdf5 hdf5::hdf5_hl LibXml2::LibXml2 NetCDF::NetCDF Boost::boost)
      if (NOT TARGET ${_simpli_dep})
        add_library(${_simpli_dep} INTERFACE IMPORTED)
      endif ()
    endforeach ()
  endif ()
  # ParaView bundles its own VTK (libvtk*-pv5.11). Take VTK from there only: mixing in
  # libvtk9's headers compiles silently (same class names) and crashes at run time.
  find_package(VTK REQUIRED
    PATHS "${ParaView_DIR}/vtk" NO_DEFAULT_PATH
    COMPONENTS CommonCore CommonDataModel CommonExecutionModel
    # Rendering: only for tests/vtk's agreement test (OpenCL rasterizer vs OpenGL). Found here,
    # at the top level, so that their imported dependencies (X11, GLEW) are visible everywhere.
    OPTIONAL_COMPONENTS Python RenderingCore RenderingOpenGL2 RenderingUI IOImage IOImport)
  set(_simpli_vtk_python "${PARAVIEW_USE_PYTHON}")
else ()
  # Plain VTK (libvtk9-dev, or ParaView's VTK via -DVTK_DIR=<paraview cmake dir>/vtk).
  find_package(VTK REQUIRED
    COMPONENTS CommonCore CommonDataModel CommonExecutionModel
    # Rendering: only for tests/vtk's agreement test (OpenCL rasterizer vs OpenGL). Found here,
    # at the top level, so that their imported dependencies (X11, GLEW) are visible everywhere.
    OPTIONAL_COMPONENTS Python RenderingCore RenderingOpenGL2 RenderingUI IOImage IOImport)
  set(_simpli_vtk_python "${VTK_WRAP_PYTHON}")
endif ()
message(STATUS "simpli: VTK ${VTK_VERSION} from ${VTK_DIR}; Python wrapping available: "
               "${_simpli_vtk_python}")

vtk_module_scan(
  MODULE_FILES     "${PROJECT_SOURCE_DIR}/filters/vtk.module"
  REQUEST_MODULES  Simpli::Filters
  PROVIDES_MODULES _simpli_vtk_modules
  ENABLE_TESTS     OFF)  # the tests live in tests/vtk, not filters/Testing
vtk_module_build(
  MODULES             ${_simpli_vtk_modules}
  INSTALL_EXPORT      SimpliFilters
  ARCHIVE_DESTINATION "${CMAKE_INSTALL_LIBDIR}"
  LIBRARY_DESTINATION "${CMAKE_INSTALL_LIBDIR}"
  HEADERS_DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/simpli/vtk"
  CMAKE_DESTINATION   "${CMAKE_INSTALL_LIBDIR}/cmake/simpli"
  TARGETS_COMPONENT   simpli_vtk_runtime
  HEADERS_COMPONENT   simpli_vtk_development
  VERSION             "${PROJECT_VERSION}"
  # "0" would be dropped by vtk_module_build (falsy); 0.x releases break ABI per minor anyway.
  SOVERSION           "${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR}")

# --- Python wrapping: package `simpli` holding the extension vtkSimpliFilters -------------
set(SIMPLI_PY_DEST "")
set(SIMPLI_BUILD_PYTHONPATH "")
set(SIMPLI_PYTHON_OK OFF)
if (SIMPLI_WRAP_PYTHON AND _simpli_vtk_python)
  if (DEFINED VTK_PYTHONPATH)
    # lib/python3/dist-packages for Debian's libvtk9 and for ParaView's bundled VTK alike.
    set(SIMPLI_PY_DEST "${VTK_PYTHONPATH}")
  else ()
    vtk_module_python_default_destination(SIMPLI_PY_DEST)
  endif ()
  vtk_module_wrap_python(
    MODULES             ${_simpli_vtk_modules}
    TARGET              Simpli::FiltersPython
    WRAPPED_MODULES     _simpli_vtk_wrapped
    INSTALL_EXPORT      SimpliFiltersPython
    PYTHON_PACKAGE      "simpli"
    MODULE_DESTINATION  "${SIMPLI_PY_DEST}"
    CMAKE_DESTINATION   "${CMAKE_INSTALL_LIBDIR}/cmake/simpli"
    LIBRARY_DESTINATION "${CMAKE_INSTALL_LIBDIR}"
    COMPONENT           simpli_vtk_python
    BUILD_STATIC        OFF
    INSTALL_HEADERS     OFF)
  # VTK generates no __init__.py for a custom PYTHON_PACKAGE; without ours `from simpli import
  # vtkSIMPLILayerGridSource` fails.
  set(SIMPLI_PY_MODULE vtkSimpliFilters) # == LIBRARY_NAME in filters/vtk.module
  configure_file("${PROJECT_SOURCE_DIR}/python/__init__.py.in"
    "${CMAKE_BINARY_DIR}/${SIMPLI_PY_DEST}/simpli/__init__.py" @ONLY)
  install(FILES "${CMAKE_BINARY_DIR}/${SIMPLI_PY_DEST}/simpli/__init__.py"
    DESTINATION "${SIMPLI_PY_DEST}/simpli"
    COMPONENT   simpli_vtk_python)
  set(SIMPLI_BUILD_PYTHONPATH "${CMAKE_BINARY_DIR}/${SIMPLI_PY_DEST}")
  list(APPEND SIMPLI_VTK_INSTALL_COMPONENTS simpli_vtk_python)

  # The wrapped module is only usable from an interpreter that has VTK's `vtkmodules` of the
  # same VTK. The pyenv python3 that may come first on PATH has none; say so at configure time
  # instead of failing obscurely in the tests.
  if (NOT Python3_EXECUTABLE)
    find_package(Python3 REQUIRED COMPONENTS Interpreter)
  endif ()
  execute_process(
    COMMAND "${Python3_EXECUTABLE}" -c "import vtkmodules.vtkCommonCore"
    RESULT_VARIABLE _simpli_vtkmodules_rc
    OUTPUT_QUIET ERROR_QUIET)
  if (_simpli_vtkmodules_rc EQUAL 0)
    set(SIMPLI_PYTHON_OK ON)
  else ()
    message(WARNING "simpli: ${Python3_EXECUTABLE} cannot import vtkmodules, so the Python "
                    "tests of the VTK module are skipped. Configure with "
                    "-DPython3_EXECUTABLE=/usr/bin/python3 (Debian's python3-paraview).")
  endif ()
endif ()

# --- ParaView plugin ---------------------------------------------------------------------
set(SIMPLI_PLUGIN_DEST "")
if (SIMPLI_USE_PARAVIEW)
  set(SIMPLI_PLUGIN_DEST "${CMAKE_INSTALL_LIBDIR}/${PARAVIEW_PLUGIN_SUBDIR}/SimpliPlugin")
  paraview_plugin_scan(
    PLUGIN_FILES            "${PROJECT_SOURCE_DIR}/plugin/paraview.plugin"
    PROVIDES_PLUGINS        _simpli_plugins
    ENABLE_BY_DEFAULT       ON
    HIDE_PLUGINS_FROM_CACHE ON)
  # XML_DOCUMENTATION is disabled in plugin/CMakeLists.txt (it needs Qt5 dev + Help).
  paraview_plugin_build(
    PLUGINS              ${_simpli_plugins}
    TARGET               Simpli::Plugins
    LIBRARY_SUBDIRECTORY "${PARAVIEW_PLUGIN_SUBDIR}"
    PLUGINS_FILE_NAME    "simpli.plugins.xml"
    PLUGINS_COMPONENT    simpli_paraview_plugins
    TARGET_COMPONENT     simpli_vtk_development
    INSTALL_HEADERS      OFF)
  list(APPEND SIMPLI_VTK_INSTALL_COMPONENTS simpli_paraview_plugins)

  # ParaView exports no pvpython/pvbatch targets.
  find_program(SIMPLI_PVPYTHON NAMES pvpython DOC "ParaView's pvpython (tests)")
  find_program(SIMPLI_PVBATCH NAMES pvbatch DOC "ParaView's pvbatch (tests)")
endif ()
