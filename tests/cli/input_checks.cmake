# Inputs refused in one message (included by tests/cli/CMakeLists.txt, label unit): output
# paths, OpenMP's thread limit, CD0 options in PETSc's own options, numbers beyond a double.
# Output paths jamsim should not make: '-' (it made a file named '-'), a line break (accepted
# from the command line, refused in a campaign file); a bad -o is named as -o, not as the
# campaign file's [campaign] output.
jamsim_cli_error(run_output_dash "small.toml: -o \"-\" is not allowed: a file name, not '-'" run ${campaigns}/small.toml -o -)
jamsim_cli_error(replica_output_dash "--output = - is not allowed: a file name, not '-'" replica --N 16 -o -)
jamsim_cli_error(run_output_folder_named_as_o "small.toml: -o \"\\.\" is not allowed: a file path, not a folder" run ${campaigns}/small.toml -o .)
add_test(NAME cli.output_line_break_refused
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/output_line_break.sh $<TARGET_FILE:jamsim> ${campaigns}/small.toml
    ${CMAKE_CURRENT_BINARY_DIR}/line_break)
set_tests_properties(cli.run_output_dash cli.replica_output_dash cli.run_output_folder_named_as_o
  cli.output_line_break_refused PROPERTIES LABELS unit)
# OpenMP's thread limit caps the threads a replica reports (it said 2 and ran 1).
add_test(NAME cli.thread_limit_caps_threads
  COMMAND bash -c "OMP_THREAD_LIMIT=1 OMP_NUM_THREADS=2 $<TARGET_FILE:jamsim> replica --N 16 --strain 0.02 -o tl.h5 > tl.txt 2>&1; rm -f tl.h5; grep -q 'on 1 thread,' tl.txt || { cat tl.txt; exit 1; }"
  WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
set_tests_properties(cli.thread_limit_caps_threads PROPERTIES LABELS unit)
# A CD0 solver option in PETSC_OPTIONS changed CD0's results while the archive recorded none
# (a resume or shard without it mixed two solvers in one archive): refused by run and replica.
jamsim_cli_error(petsc_options_environment_run "cd0_small.toml: PETSc's options \\(the PETSC_OPTIONS environment variable, or an options file PETSc reads\\) set -cd0_ksp_rtol, an option of the CD0 solver"
  run ${campaigns}/cd0_small.toml -o ${out})
jamsim_cli_error(petsc_options_environment_replica "^jamsim replica: PETSc's options .* set -cd0_pc_type, an option of the CD0 solver"
  replica --model CD0 --N 16 --strain 0.01 -o ${out})
set_tests_properties(cli.petsc_options_environment_run PROPERTIES ENVIRONMENT "EXPECT_STATUS=2;PETSC_OPTIONS=-cd0_ksp_rtol 1e-3")
set_tests_properties(cli.petsc_options_environment_replica PROPERTIES ENVIRONMENT "EXPECT_STATUS=2;PETSC_OPTIONS=-cd0_pc_type jacobi")
# A number beyond a double's range is told so ("a number" named no fault).
jamsim_cli_error(replica_phi_underflow "--phi = 1e-400 is not allowed: a number within a double's range" replica --phi 1e-400 -o ${out})
jamsim_cli_error(minimize_phi_overflow "--phi: value '1e400' is not allowed: a number within a double's range" minimize --phi 1e400)
# status of a half-run archive says its remaining time in words ("about 0 s on 1 ranks" before).
add_test(NAME cli.status_remaining_in_words
  COMMAND bash -c "rm -f rem.h5 && $<TARGET_FILE:jamsim> run ${campaigns}/small.toml --shard 0/2 -o rem.h5 > /dev/null && $<TARGET_FILE:jamsim> status rem.h5 > rem.txt; cat rem.txt; grep -Eq '^remaining: about [0-9.]+ (s|min|h) on 1 rank [(]' rem.txt"
  WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
set_tests_properties(cli.status_remaining_in_words PROPERTIES LABELS unit)
# --version with anything after it (ignored without a word before).
jamsim_cli_error(version_with_extra "^jamsim: 'extra' is not allowed after --version: it takes nothing else" --version extra)
# A number in a campaign file beyond a double's range: 1e400 got toml++'s words alone (no key),
# 4.2e-400 was taken as 0 without a word.
jamsim_campaign_error(float_overflow "float_overflow.toml:14:[0-9]+: malformed TOML: .*'1e400' .*\\(in 'points = \\[\\{N = 64, phi = 0.9, rate = 1e400\\}\\]': a number within a double's range")
jamsim_campaign_error(float_underflow "float_underflow.toml: \\[sweep\\] points rate = 4.2e-400 is not allowed: a number within a double's range")
# An invisible character in a campaign's name (a zero-width space) was taken: two names that read
# the same in every log and listing.
jamsim_campaign_error(invisible_name "invisible_name.toml: \\[campaign\\] name = .* is not allowed: a name without invisible characters \\(it holds U\\+200B\\)")
jamsim_campaign_error(name_spaces "name_spaces.toml: \\[campaign\\] name = \" spaced\" is not allowed: a name that neither starts nor ends with a space")
# An invisible character in -o (here a zero-width space) as in the campaign file's output.
jamsim_cli_error(run_output_invisible "small.toml: -o \"s.*\\.h5\" is not allowed: a path without invisible characters \\(it holds U\\+200B\\)" run ${campaigns}/small.toml -o s​.h5)
set_tests_properties(cli.run_output_invisible PROPERTIES LABELS unit)
# Values of phi or rate closer than 1e-12 relative are one state point written twice.
jamsim_campaign_error(phi_one_ulp_apart "phi_one_ulp_apart.toml: \\[sweep\\] phi holds 0.86 and 0.8600000000000001, which is not allowed: values at least 1e-12 apart")
jamsim_campaign_error(rate_one_ulp_apart "rate_one_ulp_apart.toml: \\[sweep\\] rate holds 0.001 and 0.0010000000000000002, which is not allowed")
# A list of 200000 zeros on one line is read in linear time (each value's line and column were
# found afresh: 20000 zeros took 9 s, 200000 about a quarter of an hour) and refused at once.
add_test(NAME campaign.many_zeros_read_in_linear_time
  COMMAND bash -c "set -eu; { printf '[campaign]\\nname = \"z\"\\noutput = \"z.h5\"\\n[run]\\nstrain = 0.1\\nsample_interval = 0.05\\ntransient = 0\\n[sweep]\\nN = [64]\\nrate = [1e-3]\\nseeds = 1\\nphi = [0.84'; for k in $(seq 2000); do printf ', 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0'; done; printf ']\\n'; } > zeros.toml; ! timeout 60 $<TARGET_FILE:jamsim> run zeros.toml --dry-run -o zeros.h5 2> zeros.err; cat zeros.err; grep -q 'phi = 0 is not allowed: 0 < phi < 1' zeros.err"
  WORKING_DIRECTORY ${campaign_dir})
set_tests_properties(campaign.many_zeros_read_in_linear_time PROPERTIES LABELS unit TIMEOUT 120)
