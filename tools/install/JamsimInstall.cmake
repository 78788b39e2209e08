# `cmake --install BUILD --prefix P`: the jamsim executable, the Python tools (bin/jamsim-*
# wrappers, the scripts and their package under share/jamsim/python), the campaigns, the
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
set(JAMSIM_INSTALL_PYDIR ${JAMSIM_INSTALL_DATA}/python)
# bin/ to share/jamsim/python, relative, so that the wrappers work from a moved tree.
if(IS_ABSOLUTE "${CMAKE_INSTALL_BINDIR}" OR IS_ABSOLUTE "${CMAKE_INSTALL_DATADIR}")
  message(FATAL_ERROR "jamsim installs with relative CMAKE_INSTALL_BINDIR and CMAKE_INSTALL_DATADIR "
                      "(got '${CMAKE_INSTALL_BINDIR}', '${CMAKE_INSTALL_DATADIR}'): set CMAKE_INSTALL_PREFIX instead")
endif()
file(RELATIVE_PATH _bin_to_py /prefix/${CMAKE_INSTALL_BINDIR} /prefix/${JAMSIM_INSTALL_PYDIR})

install(TARGETS jamsim RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

# The analysis package and the scripts that use it, side by side (the scripts put their own
# folder on sys.path), and one bin/ wrapper per script.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/tools/jamsim_analysis DESTINATION ${JAMSIM_INSTALL_PYDIR}
        PATTERN __pycache__ EXCLUDE PATTERN "*.pyc" EXCLUDE)
set(JAMSIM_PYTHON_TOOLS
  jamsim-analyze=jamsim_analyze.py
  jamsim-report=jamsim_report.py
  jamsim-plot-campaign=plot_campaign.py
  jamsim-plot-replica=plot_replica.py
  jamsim-analyze-scaling=analyze_scaling.py
  jamsim-analyze-jamming=analyze_jamming.py
  jamsim-transient-length=transient_length.py)
foreach(_entry IN LISTS JAMSIM_PYTHON_TOOLS)
  string(REPLACE "=" ";" _pair "${_entry}")
  list(GET _pair 0 TOOL_NAME)
  list(GET _pair 1 TOOL_SCRIPT)
  set(TOOL_PYDIR ${_bin_to_py})
  configure_file(${CMAKE_CURRENT_LIST_DIR}/python_tool.sh.in ${PROJECT_BINARY_DIR}/install/bin/${TOOL_NAME} @ONLY)
  install(PROGRAMS ${PROJECT_SOURCE_DIR}/tools/${TOOL_SCRIPT} DESTINATION ${JAMSIM_INSTALL_PYDIR})
  install(PROGRAMS ${PROJECT_BINARY_DIR}/install/bin/${TOOL_NAME} DESTINATION ${CMAKE_INSTALL_BINDIR})
endforeach()

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
foreach(topic IN ITEMS campaigns slurm tools src tests)
  install(FILES ${PROJECT_SOURCE_DIR}/${topic}/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR}/${topic})
endforeach()
