# `cmake --install`: the cosim program, its data and plot scripts, the example cases, the
# libraries with their headers, and a CMake package (find_package(cosim) gives cosim::sph,
# cosim::fem, cosim::coupling, cosim::diagnose, cosim::cosim_app).
include(CMakePackageConfigHelpers)

set(COSIM_LIBRARIES sph fem coupling diagnose cosim_app)
install(TARGETS cosim ${COSIM_LIBRARIES}
  EXPORT cosimTargets
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
foreach(part sph fem coupling diagnose app)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${part}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endforeach()

install(DIRECTORY ${PROJECT_SOURCE_DIR}/cases/data/ DESTINATION ${COSIM_SHARE_DIR}/data
  FILES_MATCHING PATTERN "*.csv" PATTERN "*.md")
install(PROGRAMS ${COSIM_PLOT_SCRIPTS} DESTINATION ${COSIM_SHARE_DIR}/scripts)
foreach(case ucs bts ctcs indentation linear-cutting)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/cases/${case}/ DESTINATION ${COSIM_SHARE_DIR}/cases/${case}
    FILES_MATCHING PATTERN "*.prm" PATTERN "README.md")
endforeach()
install(FILES ${PROJECT_SOURCE_DIR}/LICENSE ${PROJECT_SOURCE_DIR}/README.md
  DESTINATION ${CMAKE_INSTALL_DOCDIR})

set(COSIM_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/cosim)
install(EXPORT cosimTargets NAMESPACE cosim:: DESTINATION ${COSIM_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/cosimConfig.cmake.in
  ${PROJECT_BINARY_DIR}/cosimConfig.cmake INSTALL_DESTINATION ${COSIM_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/cosimConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/cosimConfig.cmake ${PROJECT_BINARY_DIR}/cosimConfigVersion.cmake
  DESTINATION ${COSIM_CMAKE_DIR})
