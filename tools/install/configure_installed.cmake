# Runs at install time (install(CODE) in JamsimInstall.cmake): copies SRC to
# DESTDIR + CMAKE_INSTALL_PREFIX + DEST with @JAMSIM_PREFIX@ and the other placeholders
# replaced, so that installed scripts name the prefix given to `cmake --install --prefix`
# (not the one of the configure step). MODE: FILE or PROGRAM; REPLACE: a list of
# FROM;TO pairs replaced literally before the placeholders (a FROM not found is an error).
# The install script runs under old policies, which would expand @VAR@ in arguments.
cmake_policy(PUSH)
cmake_policy(VERSION 3.25)
file(READ "${SRC}" text)
set(pairs ${REPLACE})
while(pairs)
  list(POP_FRONT pairs from to)
  string(FIND "${text}" "${from}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "${SRC} has no '${from}' to configure")
  endif()
  string(REPLACE "${from}" "${to}" text "${text}")
endwhile()
string(REPLACE "@JAMSIM_PREFIX@" "${CMAKE_INSTALL_PREFIX}" text "${text}")
string(REPLACE "@JAMSIM_VERSION@" "${JAMSIM_VERSION}" text "${text}")
string(REPLACE "@JAMSIM_BINDIR@" "${JAMSIM_BINDIR}" text "${text}")
string(REPLACE "@JAMSIM_PYDIR@" "${JAMSIM_PYDIR}" text "${text}")
set(out "$ENV{DESTDIR}${CMAKE_INSTALL_PREFIX}/${DEST}")
get_filename_component(dir "${out}" DIRECTORY)
file(MAKE_DIRECTORY "${dir}")
message(STATUS "Installing (configured): ${out}")
file(WRITE "${out}.tmp" "${text}")
if(MODE STREQUAL "PROGRAM")
  file(CHMOD "${out}.tmp" PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ
       GROUP_EXECUTE WORLD_READ WORLD_EXECUTE)
else()
  file(CHMOD "${out}.tmp" PERMISSIONS OWNER_READ OWNER_WRITE GROUP_READ WORLD_READ)
endif()
file(RENAME "${out}.tmp" "${out}")
cmake_policy(POP)
