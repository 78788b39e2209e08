# `cmake --install BUILD --prefix P`: the jamsim executable, the Python package
# (lib/python3/dist-packages/jamsim_analysis) and its commands (bin/jamsim-*), the campaigns, the
# Slurm scripts and modulefile templates (Lmod and Tcl). Installed scripts name the installed
# jamsim: the prefix is written into them when they are installed (tools/install/
# configure_installed.cmake), so `--prefix` at install time is the one they use.
include(GNUInstallDirs)

set(_py_default python3)
if(EXISTS /usr/bin/python3)
  set(_py_default /usr/bin/python3)
endif()
set(JAMSIM_PYTHON "${_py_default}" CACHE STRING
    "Python interpreter of the installed jamsim-* tools (environment JAMSIM_PYTHON overrides)")

set(JAMSIM_INSTALL_DATA ${CMAKE_INSTALL_DATADIR}/jamsim)
# The analysis package: Debian's layout for pure-Python packages, version-independent. Under
# the prefix /usr it is on Python's path as it is; under any other prefix put
# PREFIX/lib/python3/dist-packages on PYTHONPATH (the modulefiles do) to import it; the bin/
# commands find it themselves. -DJAMSIM_INSTALL_PYTHONDIR=lib/python3.11/dist-packages suits
# the prefix /usr/local of Debian's python3.
set(JAMSIM_INSTALL_PYTHONDIR lib/python3/dist-packages CACHE STRING
    "Folder under the install prefix that receives the Python package jamsim_analysis")
set(JAMSIM_INSTALL_PYDIR ${JAMSIM_INSTALL_PYTHONDIR})
if(IS_ABSOLUTE "${CMAKE_INSTALL_BINDIR}" OR IS_ABSOLUTE "${CMAKE_INSTALL_DATADIR}" OR IS_ABSOLUTE "${JAMSIM_INSTALL_PYDIR}")
  message(FATAL_ERROR "jamsim installs with relative CMAKE_INSTALL_BINDIR, CMAKE_INSTALL_DATADIR and "
                      "JAMSIM_INSTALL_PYTHONDIR (got '${CMAKE_INSTALL_BINDIR}', '${CMAKE_INSTALL_DATADIR}', "
                      "'${JAMSIM_INSTALL_PYDIR}'): set CMAKE_INSTALL_PREFIX instead")
endif()
# bin/ to the package's folder, relative, so that the commands work from a moved tree.
file(RELATIVE_PATH _bin_to_py /prefix/${CMAKE_INSTALL_BINDIR} /prefix/${JAMSIM_INSTALL_PYDIR})

install(TARGETS jamsim RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

# The package (tools/jamsim_analysis, described by tools/pyproject.toml) and one bin/ wrapper
# per command of pyproject.toml's [project.scripts] (NAME = "module:function"), which runs
# the function with the package's folder on PYTHONPATH. No pip is needed.
# Component `python` (also installed alone: cmake --install BUILD --component python).
install(DIRECTORY ${PROJECT_SOURCE_DIR}/tools/jamsim_analysis DESTINATION ${JAMSIM_INSTALL_PYDIR} COMPONENT python
        PATTERN __pycache__ EXCLUDE PATTERN "*.pyc" EXCLUDE)
set(_pyproject ${PROJECT_SOURCE_DIR}/tools/pyproject.toml)
set_property(DIRECTORY ${PROJECT_SOURCE_DIR} APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${_pyproject})
file(STRINGS ${_pyproject} _lines)
set(_in_scripts FALSE)
set(JAMSIM_PYTHON_TOOLS)
foreach(_line IN LISTS _lines)
  if(_line MATCHES "^\\[")
    set(_in_scripts FALSE)
    if(_line STREQUAL "[project.scripts]")
      set(_in_scripts TRUE)
    endif()
  elseif(_in_scripts AND _line MATCHES "^([a-z][a-z0-9-]*) *= *\"([a-z_][a-z0-9_.]*):([a-z_][a-z0-9_]*)\"$")
    set(TOOL_NAME ${CMAKE_MATCH_1})
    set(TOOL_MODULE ${CMAKE_MATCH_2})
    set(TOOL_FUNCTION ${CMAKE_MATCH_3})
    set(TOOL_PYDIR ${_bin_to_py})
    list(APPEND JAMSIM_PYTHON_TOOLS ${TOOL_NAME})
    configure_file(${CMAKE_CURRENT_LIST_DIR}/python_tool.sh.in ${PROJECT_BINARY_DIR}/install/bin/${TOOL_NAME} @ONLY)
    install(PROGRAMS ${PROJECT_BINARY_DIR}/install/bin/${TOOL_NAME} DESTINATION ${CMAKE_INSTALL_BINDIR}
            COMPONENT python)
  elseif(_in_scripts AND _line MATCHES "^[^#]")
    message(FATAL_ERROR "${_pyproject}: [project.scripts] line '${_line}' is not NAME = \"module:function\"")
  endif()
endforeach()
if(NOT JAMSIM_PYTHON_TOOLS)
  message(FATAL_ERROR "${_pyproject} names no commands under [project.scripts]")
endif()

# Campaigns (every file and folder under campaigns/, papers included when present).
install(DIRECTORY ${PROJECT_SOURCE_DIR}/campaigns/ DESTINATION ${JAMSIM_INSTALL_DATA}/campaigns)

# Files whose text names the install prefix, written at install time.
function(jamsim_install_configured src dest mode)
  set(replace "${ARGN}")
  install(CODE "
    set(SRC \"${src}\")
    set(DEST \"${dest}\")
    set(MODE ${mode})
    set(REPLACE \"${replace}\")
    set(JAMSIM_VERSION \"${PROJECT_VERSION}\")
    set(JAMSIM_BINDIR \"${CMAKE_INSTALL_BINDIR}\")
    set(JAMSIM_PYDIR \"${JAMSIM_INSTALL_PYDIR}\")
    include(\"${CMAKE_CURRENT_FUNCTION_LIST_DIR}/configure_installed.cmake\")")
endfunction()

# Slurm scripts: submit_campaign.sh runs the installed jamsim unless JAMSIM says otherwise.
jamsim_install_configured(${PROJECT_SOURCE_DIR}/slurm/submit_campaign.sh
  ${JAMSIM_INSTALL_DATA}/slurm/submit_campaign.sh PROGRAM
  "installed_jamsim=\\\"\\\"" "installed_jamsim=\\\"@JAMSIM_PREFIX@/${CMAKE_INSTALL_BINDIR}/jamsim\\\"")
install(PROGRAMS ${PROJECT_SOURCE_DIR}/slurm/campaign_array.sbatch ${PROJECT_SOURCE_DIR}/slurm/merge.sbatch
        DESTINATION ${JAMSIM_INSTALL_DATA}/slurm)
install(FILES ${PROJECT_SOURCE_DIR}/slurm/README.md DESTINATION ${JAMSIM_INSTALL_DATA}/slurm)

# Modulefile templates: `module use P/share/jamsim/modulefiles; module load jamsim`.
jamsim_install_configured(${CMAKE_CURRENT_LIST_DIR}/jamsim.lua.in
  ${JAMSIM_INSTALL_DATA}/modulefiles/jamsim/${PROJECT_VERSION}.lua FILE)
jamsim_install_configured(${CMAKE_CURRENT_LIST_DIR}/jamsim.tcl.in
  ${JAMSIM_INSTALL_DATA}/modulefiles/jamsim/${PROJECT_VERSION} FILE)

install(FILES ${PROJECT_SOURCE_DIR}/README.md ${PROJECT_SOURCE_DIR}/LICENSE
        DESTINATION ${CMAKE_INSTALL_DOCDIR})
# The topic pages beside the front door, in the same folders, so that its links resolve there.
foreach(page IN ITEMS campaigns/README.md campaigns/models.md campaigns/refusals.md campaigns/papers/README.md slurm/README.md
                     tools/README.md src/README.md tests/README.md tests/bench/README.md tests/bench/cd0_threads.md
                     tests/bench/cd0_solver.md)
  get_filename_component(folder ${page} DIRECTORY)
  install(FILES ${PROJECT_SOURCE_DIR}/${page} DESTINATION ${CMAKE_INSTALL_DOCDIR}/${folder})
endforeach()
