# Included by tests/cli/CMakeLists.txt (its variables: expect, out, campaigns, jamsim_cli_error).
# The commands' file options (replica, export, minimize, dry runs): empty paths, outputs that
# exist, files that cannot be made, hand-edited states.
# An empty file path (-o "", an unset shell variable) is refused before any work, by every
# command that takes one (a replica used to run to its end and fail at the write; merge took
# its first input as the output). The merge's inputs must stay unchanged.
set(empty_path_commands
  "replica|--output|replica --N 16 --phi 0.84 --rate 1e-2 --strain 0.05 -o"
  "run|--output|run ${campaigns}/other_campaign.toml -o"
  "merge|--output|merge good.h5 version.h5 -o"
  "export|--output|export good.h5 --replica 0 -o"
  "plan|--output|plan ${campaigns}/other_campaign.toml -o"
  "minimize|--lammps-data|minimize --N 16 --lammps-data")
foreach(entry IN LISTS empty_path_commands)
  jamsim_row_fields("${entry}" name option words)
  separate_arguments(words UNIX_COMMAND "${words}")
  add_test(NAME cli.empty_path_${name}
    COMMAND ${expect} "^jamsim ${name}: ${option}: value '' is not allowed: the path of a file" ${bad_dir}/none.h5
      $<TARGET_FILE:jamsim> ${words} "")
  set_tests_properties(cli.empty_path_${name} PROPERTIES LABELS unit WORKING_DIRECTORY ${bad_dir}
    FIXTURES_REQUIRED bad_archives RESOURCE_LOCK bad_archives ENVIRONMENT "EXPECT_STATUS=2;PROTECT=good.h5 version.h5")
endforeach()

# jamsim replica replaces an earlier replica file (a rerun) but no other existing file: not a
# campaign archive, not a text file, not its own --initial.
set(replica_keeps
  "archive|good.h5|good.h5|exists and is not one \\(a campaign archive, or another file\\)"
  "text|text.h5|text.h5|exists and is not one"
  "initial|replica.h5|replica.h5 --initial replica.h5|another file than --initial")
foreach(entry IN LISTS replica_keeps)
  jamsim_row_fields("${entry}" name file words regex)
  separate_arguments(words UNIX_COMMAND "${words}")
  add_test(NAME cli.replica_keeps_${name}
    COMMAND ${expect} "^jamsim replica: --output = ${file} is not allowed: .*${regex}" ${bad_dir}/none.h5
      $<TARGET_FILE:jamsim> replica --N 16 --phi 0.8 --rate 1e-2 --strain 0.01 -o ${words})
  set_tests_properties(cli.replica_keeps_${name} PROPERTIES LABELS unit WORKING_DIRECTORY ${bad_dir}
    FIXTURES_REQUIRED bad_archives RESOURCE_LOCK bad_archives ENVIRONMENT "EXPECT_STATUS=2;PROTECT=${file}")
endforeach()
# ... nor a file it cannot create: found before the run, not at its end (root may write
# anywhere that access() asks about, /proc included).
add_test(NAME cli.replica_output_uncreatable
  COMMAND ${expect} "^jamsim replica: --output = /proc/jamsim-q.h5 is not allowed: a file in a directory where files can be made" ${bad_dir}/none.h5
    $<TARGET_FILE:jamsim> replica --N 16 --phi 0.8 --rate 1e-2 --strain 0.01 -o /proc/jamsim-q.h5)
set_tests_properties(cli.replica_output_uncreatable PROPERTIES LABELS unit ENVIRONMENT "EXPECT_STATUS=2")
# A campaign's [run] initial that is not a campaign archive gets the same words.
add_test(NAME cli.campaign_initial_replica_file
  COMMAND ${expect} "initial_replica_file.toml: \\[run\\] initial = .replica.h5. is not allowed: a jamsim campaign archive or a LAMMPS data file \\('replica.h5' is a single-replica file"
    ${bad_dir}/initial-out.h5 $<TARGET_FILE:jamsim> run ${campaigns}/initial_replica_file.toml
  WORKING_DIRECTORY ${bad_dir})
set_tests_properties(cli.campaign_initial_replica_file PROPERTIES LABELS unit FIXTURES_REQUIRED bad_archives
  RESOURCE_LOCK bad_archives ENVIRONMENT "EXPECT_STATUS=2;PROTECT=replica.h5")
# jamsim replica checks what jamsim run checks: the cell grid of a dilute box, the memory of
# a large N (4e9 disks of RD0 need about 1 TB; each used to run into std::bad_alloc).
add_test(NAME cli.replica_phi_too_dilute
  COMMAND ${expect} "^jamsim replica: --phi = 1e-08 is not allowed: phi >= 1.2e-08 at N = 64, or N <= 52 at phi = 1e-08" ${bad_dir}/none.h5
    $<TARGET_FILE:jamsim> replica --N 64 --phi 1e-8 --rate 1e-2 --strain 0.01 -o ${bad_dir}/none.h5)
add_test(NAME cli.replica_memory
  COMMAND ${expect} "^jamsim replica: a replica of N = 4000000000 at phi = 0.84 needs about 1.0[0-9] TB of memory, but this node has" ${bad_dir}/none.h5
    $<TARGET_FILE:jamsim> replica --N 4000000000 --phi 0.84 --rate 1e-2 --strain 0.01 -o ${bad_dir}/none.h5)
set_tests_properties(cli.replica_phi_too_dilute cli.replica_memory PROPERTIES LABELS unit ENVIRONMENT "EXPECT_STATUS=2")
# A final state that jamsim cannot have written (a hand-edited archive): export writes no
# LAMMPS file of it (it wrote nan positions or a negative box, exit 0), --initial starts no
# replica from it.
foreach(entry "final_nan|x = nan at disk 3" "box_negative|box_side = -1"
    "box_strain_far|box_strain = 7 \\(the box keeps it from -1/2 to 1/2\\)")
  jamsim_row_fields("${entry}" name words)
  add_test(NAME archive_file.export_${name}
    COMMAND ${expect} "^jamsim export: replica 0 of '${name}.h5' cannot be exported: its final state has ${words}; jamsim writes no such state"
      ${bad_dir}/exported.data $<TARGET_FILE:jamsim> export ${name}.h5 --replica 0 -o exported.data
    WORKING_DIRECTORY ${bad_dir})
  add_test(NAME archive_file.initial_${name}
    COMMAND ${expect} "^jamsim replica: --initial = ${name}.h5 is not allowed: replica 0's final state has ${words}"
      ${bad_dir}/q.h5 $<TARGET_FILE:jamsim> replica --N 64 --phi 0.8 --rate 1e-2 --strain 0.01 --initial ${name}.h5 -o q.h5
    WORKING_DIRECTORY ${bad_dir})
  set_tests_properties(archive_file.export_${name} archive_file.initial_${name} PROPERTIES LABELS unit
    FIXTURES_REQUIRED bad_archives RESOURCE_LOCK bad_archives ENVIRONMENT "EXPECT_STATUS=2;PROTECT=${name}.h5")
endforeach()
# ... and does replace an earlier replica file.
add_test(NAME cli.replica_replaces_replica_file
  COMMAND bash -c "set -e; rm -f again.h5; $<TARGET_FILE:jamsim> replica --N 16 --phi 0.8 --rate 1e-2 --strain 0.01 -o again.h5 > /dev/null 2>&1; $<TARGET_FILE:jamsim> replica --N 16 --phi 0.8 --rate 1e-2 --strain 0.02 -o again.h5 > /dev/null 2>&1; /usr/bin/python3 -c \"import h5py, sys; sys.exit(0 if abs(h5py.File('again.h5').attrs['strain'] - 0.02) < 1e-12 else 1)\""
  WORKING_DIRECTORY ${bad_dir})
set_tests_properties(cli.replica_replaces_replica_file PROPERTIES LABELS unit)
# --ranks and --shards of a dry run: a whole number >= 1 (--ranks at most 2^20, as plan's
# cores: 10^9 was blamed on the campaign's memory), said in those words.
foreach(case "ranks|0|from 1 to 1048576" "ranks|1000000000|from 1 to 1048576" "shards|0|>= 1")
  jamsim_row_fields("${case}" option value allowed)
  add_test(NAME cli.dry_run_${option}_${value}
    COMMAND ${expect} "^jamsim run: --${option}: value ${value} is not allowed: a whole number of ${option} ${allowed}" ${bad_dir}/none.h5
      $<TARGET_FILE:jamsim> run ${campaigns}/other_campaign.toml --dry-run --${option} ${value})
  set_tests_properties(cli.dry_run_${option}_${value} PROPERTIES LABELS unit ENVIRONMENT "EXPECT_STATUS=2")
endforeach()
# jamsim minimize refuses what its campaign keys refuse (validate() of one RAND replica), naming
# the option (each used to run: a seed of -1 as 2^64 - 1, a negative or NaN tolerance, an
# unknown minimiser with status 1, phi = 1e-300 into the neighbour list's overflow).
set(minimize_refusals
  "seed_negative|--seed -1|--seed: value '-1' is not allowed: a whole number"
  "n_hex|--N 0x40|--N: value '0x40' is not allowed: a whole number"
  "energy_floor|--energy-floor nan|--energy-floor = nan is not allowed: a finite number, 0 < energy_floor < 0.01"
  "energy_floor_huge|--energy-floor 1e300|--energy-floor = 1e\\+300 is not allowed: 0 < energy_floor < 0.01"
  "force_tol|--force-tol -1|--force-tol = -1 is not allowed: 0 <= force_tol < 1"
  "force_tol_huge|--force-tol 1e300|--force-tol = 1e\\+300 is not allowed: 0 <= force_tol < 1"
  "no_stopping_rule|--force-tol 0 --force-tol-abs 0|--force-tol = 0 is not allowed: force_tol > 0 or force_tol_abs > 0"
  "max_iterations|--max-iterations -5|--max-iterations: value -5 is not allowed: a whole number of iterations >= 1"
  "alpha|--alpha 1|--alpha = 1 is not allowed: 1 < alpha <= 20"
  "minimizer|--minimizer bogus|--minimizer = bogus is not allowed: cg, cg-pr, fire"
  "phi_too_dilute|--phi 1e-300|--phi = 1e-300 is not allowed: phi >= 3e-09 at N = 16")
foreach(entry IN LISTS minimize_refusals)
  jamsim_row_fields("${entry}" name words regex)
  separate_arguments(words UNIX_COMMAND "${words}")
  add_test(NAME cli.minimize_refuses_${name}
    COMMAND ${expect} "${regex}" ${bad_dir}/none.h5 $<TARGET_FILE:jamsim> minimize --N 16 ${words})
  set_tests_properties(cli.minimize_refuses_${name} PROPERTIES LABELS unit ENVIRONMENT "EXPECT_STATUS=2")
endforeach()
# jamsim minimize checks its memory, and that its data file can be made, before the work (it
# ended in std::bad_alloc, or failed after the minimisation).
add_test(NAME cli.minimize_memory
  COMMAND ${expect} "^jamsim minimize: a replica of N = 4294967312 at phi = 0.85 needs about 1.1[0-9] TB of memory" ${bad_dir}/none.h5
    $<TARGET_FILE:jamsim> minimize --N 4294967312)
add_test(NAME cli.minimize_data_folder_missing
  COMMAND ${expect} "^jamsim minimize: --lammps-data = no_such_folder/x.data is not allowed: a file in an existing directory" ${bad_dir}/none.h5
    $<TARGET_FILE:jamsim> minimize --N 16 --lammps-data no_such_folder/x.data)
set_tests_properties(cli.minimize_memory cli.minimize_data_folder_missing PROPERTIES LABELS unit ENVIRONMENT "EXPECT_STATUS=2")
jamsim_cli_error(size_ratio_overflows "--size-ratio = 1e\\+308 is not allowed: 1 <= size_ratio <= 100"
  replica --N 16 --size-ratio 1e308 -o ${out})
# 1e10 was refused for the disk space of g_y's bins; a skin of 1e300 blamed N.
jamsim_cli_error(size_ratio_too_large "--size-ratio = 10000000000 is not allowed: 1 <= size_ratio <= 100"
  replica --size-ratio 1e10 -o ${out})
jamsim_cli_error(skin_too_large "--skin = 1e\\+300 is not allowed: a skin that the box of some N holds twice over"
  replica --skin 1e300 -o ${out})
# jamsim minimize --lammps-data overwrites nothing (it replaced archives and campaign files).
add_test(NAME cli.minimize_keeps_existing_file
  COMMAND ${expect} "^jamsim minimize: --lammps-data = .*other_campaign.toml is not allowed: a new file \\(it exists" ${bad_dir}/none.h5
    $<TARGET_FILE:jamsim> minimize --N 16 --lammps-data ${campaigns}/other_campaign.toml)
set_tests_properties(cli.minimize_keeps_existing_file PROPERTIES LABELS unit
  ENVIRONMENT "EXPECT_STATUS=2;PROTECT=${campaigns}/other_campaign.toml")
# The planned run's options without --dry-run are refused (they were silently ignored:
# `run --ranks 4` ran on one rank).
foreach(option ranks time-limit summary serial-fraction probe-seconds)
  set(words --${option})
  if(option STREQUAL "serial-fraction")
    list(APPEND words 0.5)
  elseif(NOT option STREQUAL "summary")
    list(APPEND words 4)
  endif()
  add_test(NAME cli.run_${option}_without_dry_run
    COMMAND ${expect} "^jamsim run: --${option} is not allowed without --dry-run" ${bad_dir}/plain_run.h5
      $<TARGET_FILE:jamsim> run ${campaigns}/other_campaign.toml ${words} -o ${bad_dir}/plain_run.h5)
  set_tests_properties(cli.run_${option}_without_dry_run PROPERTIES LABELS unit ENVIRONMENT "EXPECT_STATUS=2")
endforeach()
# ... and a run's own options with --dry-run (the dry run ignored --shard 1/2 and listed the
# whole campaign).
foreach(entry "shard|1/2" "retry-failed|" "checkpoint-every|5" "progress|lines" "progress-interval|3")
  jamsim_row_fields("${entry}" option value)
  add_test(NAME cli.run_${option}_with_dry_run
    COMMAND ${expect} "^jamsim run: --${option} is not allowed with --dry-run: it changes how a run runs" ${bad_dir}/plain_run.h5
      $<TARGET_FILE:jamsim> run ${campaigns}/other_campaign.toml --dry-run --${option} ${value} -o ${bad_dir}/plain_run.h5)
  set_tests_properties(cli.run_${option}_with_dry_run PROPERTIES LABELS unit ENVIRONMENT "EXPECT_STATUS=2")
endforeach()
# jamsim replica: the run length follows the rate (it said "--time ... not used by model RD0").
jamsim_cli_error(replica_time_at_rate "--time = 1 is not allowed: --time only at --rate 0 \\(dynamics without shear\\); at rate = 0.01 the run length is --strain"
  replica --N 16 --rate 1e-2 --time 1 -o ${bad_dir}/none.h5)
jamsim_cli_error(replica_strain_at_rate_zero "--strain = 1 is not allowed: --strain only at --rate > 0; at rate 0 the run length is --time"
  replica --N 16 --rate 0 --time 1 --strain 1 -o ${bad_dir}/none.h5)
# jamsim replica: an empty --initial, and --initial-match without --initial, say what they need
# (both said "not used by model RD0").
add_test(NAME cli.replica_initial_empty
  COMMAND ${expect} "--initial = '' is not allowed: the path of an archive or a LAMMPS data file" ${bad_dir}/q.h5
    $<TARGET_FILE:jamsim> replica --N 16 --phi 0.8 --rate 1e-2 --strain 0.01 --initial "" -o ${bad_dir}/q.h5)
add_test(NAME cli.replica_initial_match_alone
  COMMAND ${expect} "--initial-match = id is not allowed: only with --initial" ${bad_dir}/q.h5
    $<TARGET_FILE:jamsim> replica --N 16 --phi 0.8 --rate 1e-2 --strain 0.01 --initial-match id -o ${bad_dir}/q.h5)
set_tests_properties(cli.replica_initial_empty cli.replica_initial_match_alone PROPERTIES LABELS unit
  ENVIRONMENT "EXPECT_STATUS=2")

# New-file outputs that are symbolic links (a loop, a dangling link): refused, the links left
# as they are (minimize and replica wrote beside and renamed over the link, exit 0).
add_test(NAME cli.output_symbolic_links_refused
  COMMAND bash -c "set -u; cd \"$1\" && rm -rf links && mkdir links && cd links && ln -s A B && ln -s B A && ln -s missing/target.data dl.data && for cmd in 'minimize --N 32 --phi 0.9 --lammps-data A' 'minimize --N 32 --phi 0.9 --lammps-data dl.data' 'replica --N 16 --strain 0.01 -o dl.data' 'replica --N 16 --strain 0.01 -o A'; do out=$(\"$0\" $cmd 2>&1); rc=$?; [ $rc -eq 2 ] || { echo \"$cmd: exit $rc\"; exit 1; }; echo \"$out\" | grep -q 'is not allowed: a file.s own path, not a symbolic link' || { echo \"$cmd: $out\"; exit 1; }; done; test -L A && test -L B && test -L dl.data && test ! -e missing"
    $<TARGET_FILE:jamsim> ${CMAKE_CURRENT_BINARY_DIR})
set_tests_properties(cli.output_symbolic_links_refused PROPERTIES LABELS unit)

# An output name longer than the folder allows (with its temporary's suffix): refused before
# the replica runs (it ran the whole replica, then failed to write it, exit 1).
add_test(NAME cli.output_name_too_long
  COMMAND bash -c "cd \"$1\" && name=$(printf 'n%.0s' $(seq 300)) && for cmd in \"replica --N 16 --strain 0.01 -o $name.h5\" \"minimize --N 32 --phi 0.9 --lammps-data $name.data\"; do out=$(\"$0\" $cmd 2>&1); rc=$?; [ $rc -eq 2 ] || { echo \"exit $rc\"; exit 1; }; echo \"$out\" | grep -q 'is not allowed: a file name of at most [0-9]* bytes in that folder (this one has 30[0-9])' || { echo \"$out\"; exit 1; }; done"
    $<TARGET_FILE:jamsim> ${CMAKE_CURRENT_BINARY_DIR})
set_tests_properties(cli.output_name_too_long PROPERTIES LABELS unit)

# A loop of symbolic links as --initial: refused naming the option and the loop (it was called
# missing by a later reader, exit 1).
add_test(NAME cli.initial_link_loop
  COMMAND bash -c "cd \"$1\" && rm -f loopA loopB && ln -s loopA loopB && ln -s loopB loopA && out=$(\"$0\" replica --N 16 --strain 0.01 --initial loopA -o q.h5 2>&1); rc=$?; [ $rc -eq 2 ] || { echo \"exit $rc: $out\"; exit 1; }; echo \"$out\" | grep -q \"^jamsim replica: --initial = loopA is not allowed: a jamsim campaign archive or a LAMMPS data file: 'loopA' is a symbolic link that leads to no file (a loop of links)\" || { echo \"$out\"; exit 1; }; test ! -e q.h5"
    $<TARGET_FILE:jamsim> ${CMAKE_CURRENT_BINARY_DIR})
set_tests_properties(cli.initial_link_loop PROPERTIES LABELS unit)

# TMPDIR that is not a writable folder, for the commands that start MPI: refused in jamsim's
# words (Open MPI's "A call to mkdir was unable to create the desired directory", exit 1).
add_test(NAME cli.tmpdir_not_a_folder
  COMMAND ${expect} "^jamsim: TMPDIR = '/etc/passwd' is not allowed: a writable folder" ${bad_dir}/none.h5
    $<TARGET_FILE:jamsim> run ${campaigns}/other_campaign.toml -o ${bad_dir}/none.h5)
set_tests_properties(cli.tmpdir_not_a_folder PROPERTIES LABELS unit ENVIRONMENT "EXPECT_STATUS=2;TMPDIR=/etc/passwd")
