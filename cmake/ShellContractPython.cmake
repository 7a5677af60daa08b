# SHELLCONTRACT_BUILD_PYTHON: on by default when pybind11 and the Python development files (with
# numpy) are found, silently off otherwise. The interpreter is Debian's /usr/bin/python3 unless
# Python_EXECUTABLE says otherwise: a pyenv or venv python3 first on PATH usually lacks numpy and
# pybind11, and the module must be built for the interpreter that runs it.
if(NOT DEFINED Python_EXECUTABLE AND EXISTS /usr/bin/python3)
  set(Python_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "Python interpreter the module is built for")
endif()
set(_shellcontract_python_default OFF)
if(NOT DEFINED SHELLCONTRACT_BUILD_PYTHON OR SHELLCONTRACT_BUILD_PYTHON)
  find_package(Python 3 QUIET COMPONENTS Interpreter Development.Module NumPy)
  if(Python_FOUND)
    set(PYBIND11_FINDPYTHON ON)  # reuse the Python found above (FindPython), not the old FindPythonLibs
    find_package(pybind11 2.6 CONFIG QUIET)
  endif()
  if(Python_FOUND AND pybind11_FOUND)
    set(_shellcontract_python_default ON)
  endif()
endif()
option(SHELLCONTRACT_BUILD_PYTHON "Build the Python module (pybind11)" ${_shellcontract_python_default})
if(SHELLCONTRACT_BUILD_PYTHON AND NOT (Python_FOUND AND pybind11_FOUND))
  message(FATAL_ERROR "SHELLCONTRACT_BUILD_PYTHON is on, but Python ${Python_EXECUTABLE} with "
                      "development files and numpy, or pybind11, was not found "
                      "(Debian: python3-dev python3-numpy pybind11-dev)")
endif()
if(SHELLCONTRACT_BUILD_PYTHON)
  # The module is a shared object with the static library inside: its code must be
  # position-independent (a thread-local in CGAL's headers otherwise fails to link).
  set_target_properties(shellcontract shellcontract_reader PROPERTIES POSITION_INDEPENDENT_CODE ON)
endif()

# Where `cmake --install` puts the package (the module and the pure-Python files), relative to the
# prefix: lib/python3.X/dist-packages for the interpreter the module is built for, which Debian's
# python3.X has on its path for both the prefix /usr/local (the default) and /usr (its
# lib/python3/dist-packages is there for /usr only, so a default install did not import).
# `shellcontract sweep` finds it relative to its own executable (cli/sweep.cpp), so an installed
# tree works wherever it is installed (--prefix P) without PYTHONPATH.
if(Python_VERSION_MAJOR AND Python_VERSION_MINOR)
  set(_python_install_default "lib/python${Python_VERSION_MAJOR}.${Python_VERSION_MINOR}/dist-packages")
else()
  set(_python_install_default "lib/python3/dist-packages")
endif()
set(SHELLCONTRACT_PYTHON_INSTALL_DIR "${_python_install_default}" CACHE STRING
    "Folder (relative to the install prefix) the shellcontract Python package is installed into")
if(IS_ABSOLUTE "${SHELLCONTRACT_PYTHON_INSTALL_DIR}" OR IS_ABSOLUTE "${CMAKE_INSTALL_BINDIR}")
  # Not relocatable: the CLI looks in the absolute folder.
  set(_python_dir "${SHELLCONTRACT_PYTHON_INSTALL_DIR}")
  if(NOT IS_ABSOLUTE "${_python_dir}")
    set(_python_dir "${CMAKE_INSTALL_PREFIX}/${_python_dir}")
  endif()
  set(SHELLCONTRACT_PYTHON_DIR_FROM_BIN "${_python_dir}")
else()
  file(RELATIVE_PATH SHELLCONTRACT_PYTHON_DIR_FROM_BIN "/prefix/${CMAKE_INSTALL_BINDIR}"
       "/prefix/${SHELLCONTRACT_PYTHON_INSTALL_DIR}")
endif()
target_compile_definitions(shellcontract_cli_code PRIVATE
  SHELLCONTRACT_PYTHON_DIR_FROM_BIN="${SHELLCONTRACT_PYTHON_DIR_FROM_BIN}")
