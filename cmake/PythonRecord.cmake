# Run by `cmake --install` (python/CMakeLists.txt, install(CODE)) after the Python package and its
# dist-info are installed: writes the dist-info's RECORD, the list of the files installed for the
# package, which pip reads (`pip show -f`, `pip uninstall`). Each file with its SHA-256 and size,
# read off the installed copy, as PyPA's "Recording installed projects" has them (the digest in
# URL-safe base64 without padding). In: SHELLCONTRACT_RECORD_SITE (the package's folder, relative to
# the prefix or absolute), SHELLCONTRACT_RECORD_DIST_INFO (the dist-info's name),
# SHELLCONTRACT_RECORD_FILES (the installed files, relative to that folder), SHELLCONTRACT_RECORD_OUT
# (where RECORD is written before it is installed).

# A digest given in hexadecimal, in URL-safe base64 without padding: 3 bytes (6 hex digits) give
# 4 characters; a last 2 bytes give 3, a last byte 2.
function(_shellcontract_record_base64 hex out)
  set(alphabet "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_")
  string(LENGTH "${hex}" n)
  set(result "")
  set(i 0)
  while(i LESS n)
    math(EXPR left "${n} - ${i}")
    if(left GREATER 6)
      set(left 6)
    endif()
    string(SUBSTRING "${hex}" ${i} ${left} chunk)
    math(EXPR value "0x${chunk} << (4 * (6 - ${left}))")
    if(left EQUAL 6)
      set(chars 4)
    elseif(left EQUAL 4)
      set(chars 3)
    else()
      set(chars 2)
    endif()
    foreach(k RANGE 0 3)
      if(k LESS chars)
        math(EXPR index "(${value} >> (18 - 6 * ${k})) & 63")
        string(SUBSTRING "${alphabet}" ${index} 1 c)
        string(APPEND result "${c}")
      endif()
    endforeach()
    math(EXPR i "${i} + ${left}")
  endwhile()
  set(${out} "${result}" PARENT_SCOPE)
endfunction()

set(_site "${SHELLCONTRACT_RECORD_SITE}")
if(NOT IS_ABSOLUTE "${_site}")
  set(_site "${CMAKE_INSTALL_PREFIX}/${_site}")
endif()
set(_record "")
foreach(_f ${SHELLCONTRACT_RECORD_FILES})
  set(_installed "$ENV{DESTDIR}${_site}/${_f}")
  if(NOT EXISTS "${_installed}")
    message(FATAL_ERROR "RECORD of ${SHELLCONTRACT_RECORD_DIST_INFO}: ${_installed} was not installed")
  endif()
  file(SIZE "${_installed}" _size)
  file(SHA256 "${_installed}" _hex)
  _shellcontract_record_base64("${_hex}" _digest)
  string(APPEND _record "${_f},sha256=${_digest},${_size}\n")
endforeach()
# RECORD cannot hold its own digest: its line has none, as the format says.
string(APPEND _record "${SHELLCONTRACT_RECORD_DIST_INFO}/RECORD,,\n")
file(WRITE "${SHELLCONTRACT_RECORD_OUT}" "${_record}")
file(INSTALL DESTINATION "${_site}/${SHELLCONTRACT_RECORD_DIST_INFO}" TYPE FILE FILES "${SHELLCONTRACT_RECORD_OUT}")
