# The man page shellcontract.1, made at build time from the CLI's own help (the tool's --help and
# each command's) by cmake/ManPage.cmake, so that it cannot drift from the CLI; installed to
# <mandir>/man1 (`man shellcontract`). A cross-compiled CLI does not run here: no page then.
if(CMAKE_CROSSCOMPILING)
  message(STATUS "Cross-compiling: no man page (it is made by running the CLI it documents)")
  return()
endif()
set(SHELLCONTRACT_MAN_PAGE ${PROJECT_BINARY_DIR}/man/shellcontract.1)
set(_man_depends shellcontract_cli ${PROJECT_SOURCE_DIR}/cmake/ManPage.cmake)
set(_man_optional "")
if(SHELLCONTRACT_BUILD_PYTHON)
  # `shellcontract sweep --help` is the Python package's (argparse): the module and its files.
  file(GLOB _man_python CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/python/shellcontract/*.py)
  list(APPEND _man_depends shellcontract_python shellcontract_python_files ${_man_python})
else()
  set(_man_optional sweep)
endif()
add_custom_command(OUTPUT ${SHELLCONTRACT_MAN_PAGE}
  COMMAND ${CMAKE_COMMAND} -DCLI=$<TARGET_FILE:shellcontract_cli> -DOUT=${SHELLCONTRACT_MAN_PAGE}
          "-DTITLE=ShellContract ${PROJECT_VERSION}" "-DDESCRIPTION=${PROJECT_DESCRIPTION}"
          "-DOPTIONAL_COMMANDS=${_man_optional}" -P ${PROJECT_SOURCE_DIR}/cmake/ManPage.cmake
  DEPENDS ${_man_depends}
  COMMENT "Man page ${SHELLCONTRACT_MAN_PAGE} from the CLI's --help" VERBATIM)
add_custom_target(shellcontract_man_page ALL DEPENDS ${SHELLCONTRACT_MAN_PAGE})
install(FILES ${SHELLCONTRACT_MAN_PAGE} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
