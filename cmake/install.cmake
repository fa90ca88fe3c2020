# Install rules: the libraries, the public headers, the CMake package (find_package(topotet CONFIG)
# gives topotet::topotet) and a pkg-config file. Included by the top CMakeLists.txt when
# TOPOTET_INSTALL is on (the default when topotet is the top-level project).
include(CMakePackageConfigHelpers)

set(TOPOTET_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/topotet)
set(topotet_install_targets topotet_engine topotet_metrics topotet_topotet)
if(TARGET topotet_c)
  list(APPEND topotet_install_targets topotet_c)
endif()
if(TARGET topotet_fortran)
  list(APPEND topotet_install_targets topotet_fortran)
endif()
# topotet::mpi (TOPOTET_MPI): the package then finds MPI for its consumers.
set(TOPOTET_PACKAGE_HAS_MPI OFF)
if(TARGET topotet_mpi)
  list(APPEND topotet_install_targets topotet_mpi)
  set(TOPOTET_PACKAGE_HAS_MPI ON)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/mpi/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} FILES_MATCHING PATTERN "*.h")
endif()
if(TARGET topotet-mpi)
  install(TARGETS topotet-mpi RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()

# topotet::io_vtk (the VTK formats) in an export set of its own, loaded only when a consumer asks
# for the component: the package then finds VTK, and only then.
set(TOPOTET_PACKAGE_HAS_VTK OFF)
if(TARGET topotet_io_vtk)
  set(TOPOTET_PACKAGE_HAS_VTK ON)
  string(REPLACE ";" " " TOPOTET_PACKAGE_VTK_COMPONENTS "${TOPOTET_VTK_COMPONENTS}")
  install(TARGETS topotet_io_vtk EXPORT topotetVtkTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
    INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/io/vtk/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} FILES_MATCHING PATTERN "*.h")
  install(EXPORT topotetVtkTargets NAMESPACE topotet:: DESTINATION ${TOPOTET_CMAKE_DIR})
endif()

install(TARGETS ${topotet_install_targets} EXPORT topotetTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/engine/include/ ${PROJECT_SOURCE_DIR}/io/include/
  ${PROJECT_SOURCE_DIR}/generate/include/ ${PROJECT_SOURCE_DIR}/metrics/include/ ${PROJECT_SOURCE_DIR}/outofcore/include/
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} FILES_MATCHING PATTERN "*.h")
install(FILES ${PROJECT_BINARY_DIR}/include/topotet/version.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/topotet)
if(TARGET topotet_c)
  install(FILES ${PROJECT_SOURCE_DIR}/capi/include/topotet/topotet_c.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/topotet)
endif()
if(TARGET topotet_fortran)
  # The compiled module file (compiler-specific, like every .mod) beside the headers.
  install(FILES ${TOPOTET_FORTRAN_MODULE_DIR}/topotet.mod DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/topotet/fortran)
endif()
if(TARGET topotet)
  install(TARGETS topotet RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
if(TARGET topotet_vtk)  # the tools' VTK module (cli/vtk_loader.cpp looks for it there)
  install(TARGETS topotet_vtk LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/topotet)
endif()

install(EXPORT topotetTargets NAMESPACE topotet:: DESTINATION ${TOPOTET_CMAKE_DIR})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/topotetConfig.cmake.in
  ${PROJECT_BINARY_DIR}/topotetConfig.cmake INSTALL_DESTINATION ${TOPOTET_CMAKE_DIR})
# 0.x: a minor release may break the API, so only the same major.minor is compatible.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/topotetConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/topotetConfig.cmake ${PROJECT_BINARY_DIR}/topotetConfigVersion.cmake
  DESTINATION ${TOPOTET_CMAKE_DIR})

# pkg-config: paths relative to the .pc file, so that `cmake --install --prefix ANY` works.
file(RELATIVE_PATH TOPOTET_PC_TO_PREFIX /prefix/${CMAKE_INSTALL_LIBDIR}/pkgconfig /prefix)
set(TOPOTET_PC_LIBS "-ltopotet_metrics -ltopotet_engine")
if(TARGET topotet_c)
  set(TOPOTET_PC_LIBS "-ltopotet_c ${TOPOTET_PC_LIBS}")
endif()
configure_file(${CMAKE_CURRENT_LIST_DIR}/topotet.pc.in ${PROJECT_BINARY_DIR}/topotet.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/topotet.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
