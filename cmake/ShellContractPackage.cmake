# `cmake --install` puts the library, its public headers, the CLI and a CMake package in the
# prefix, so that another project can write
#   find_package(ShellContract 0.2 REQUIRED)
#   target_link_libraries(app PRIVATE ShellContract::shellcontract)
# The package carries only the library's own dependencies (Eigen, CGAL, TBB); Boost's
# program_options (CLI) and GoogleTest (tests) stay out of it.
include(CMakePackageConfigHelpers)
set(SHELLCONTRACT_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/ShellContract)

set_target_properties(shellcontract PROPERTIES EXPORT_NAME shellcontract)
add_library(ShellContract::shellcontract ALIAS shellcontract)
install(TARGETS shellcontract EXPORT ShellContractTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS shellcontract_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/shellcontract DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
# What a package must carry with the binaries: the third-party components and their licences.
install(FILES ${PROJECT_SOURCE_DIR}/NOTICE DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(EXPORT ShellContractTargets NAMESPACE ShellContract:: DESTINATION ${SHELLCONTRACT_CMAKE_DIR})

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/ShellContractConfig.cmake.in
  ${PROJECT_BINARY_DIR}/ShellContractConfig.cmake INSTALL_DESTINATION ${SHELLCONTRACT_CMAKE_DIR})
# 0.x: a minor version may change the API, so 0.2 accepts 0.2.z only.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/ShellContractConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/ShellContractConfig.cmake ${PROJECT_BINARY_DIR}/ShellContractConfigVersion.cmake
  DESTINATION ${SHELLCONTRACT_CMAKE_DIR})
