# Included by tests/cli/CMakeLists.txt (its variables: expect, out, campaigns, jamsim_cli_error).
# Files given as archives or outputs: bad kinds, outputs that name no writable file, merges.
# Splits a table row "a|b|c" into the caller's variables named after it, in order.
function(jamsim_row_fields row)
  string(REPLACE "|" ";" parts "${row}")
  set(i 0)
  foreach(var IN LISTS ARGN)
    list(GET parts ${i} value)
    set(${var} "${value}" PARENT_SCOPE)
    math(EXPR i "${i} + 1")
  endforeach()
endfunction()
# Bad files given as archives: status, run and merge say which kind, exit 2, change nothing.
set(bad_dir ${CMAKE_CURRENT_BINARY_DIR}/bad_archives)
file(MAKE_DIRECTORY ${bad_dir})
add_test(NAME archive_file.make_bad_files
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/make_bad_archives.sh $<TARGET_FILE:jamsim> ${campaigns}/other_campaign.toml
  WORKING_DIRECTORY ${bad_dir})
set_tests_properties(archive_file.make_bad_files PROPERTIES LABELS unit FIXTURES_SETUP bad_archives)
set(bad_kinds
  "missing|missing.h5|'missing.h5' does not exist"
  "directory|a_directory|'a_directory' is a directory, not a campaign archive"
  "empty|empty.h5|'empty.h5' is empty \\(0 bytes\\), not a campaign archive"
  "not_hdf5|text.h5|'text.h5' is not an HDF5 file \\(no HDF5 signature in its 15 bytes\\)"
  "truncated|truncated.h5|'truncated.h5' is truncated: its HDF5 superblock says [0-9]+ bytes, the file has [0-9]+"
  "not_jamsim|plain.h5|'plain.h5' is an HDF5 file but not a jamsim campaign archive"
  "replica_file|replica.h5|'replica.h5' is a single-replica file of jamsim replica, not a campaign archive"
  "other_layout|layout.h5|'layout.h5' has archive layout 2 .*this jamsim reads layout 4"
  "other_version|version.h5|'version.h5' was written by another version of jamsim \\(jamsim campaign v1. this one writes jamsim campaign v7\\)"
  "status_rows|status_rows.h5|'status_rows.h5' is damaged: /replicas/status has 2 entries \\(n_replicas is 1\\)"
  "status_value|status_value.h5|'status_value.h5' is damaged: /replicas/status\\[0\\] is 9 \\(0 pending, 1 running, 2 done, 3 failed\\)"
  "series_cut|series_cut.h5|'series_cut.h5' is damaged: /timeseries/pressure is 1 x 2 where /timeseries/[a-z_]+ is 1 x [0-9]+"
  "final_cut|final_cut.h5|'final_cut.h5' is damaged: /final/y is 64 entries where /final/x is 3 entries"
  "no_series|no_series.h5|'no_series.h5' is damaged: it has no /timeseries"
  "ranks_text|ranks_text.h5|'ranks_text.h5' is damaged: its attribute n_ranks is not one integer"
  "n_nan|n_nan.h5|'n_nan.h5' is damaged: /replicas/N\\[0\\] is nan \\(a whole number of disks from 1 to the [0-9]+ of /final/x\\)"
  "n_zero|n_zero.h5|'n_zero.h5' is damaged: /replicas/N\\[0\\] is 0 \\(a whole number of disks"
  "n_huge|n_huge.h5|'n_huge.h5' is damaged: /replicas/N\\[0\\] is 1000000000000 \\(a whole number of disks"
  "offset_far|offset_far.h5|'offset_far.h5' is damaged: /replicas/particle_offset\\[0\\] is 1000000000000 where the disks of the replicas before it add up to 0"
  "samples_many|samples_many.h5|'samples_many.h5' is damaged: /replicas/n_samples\\[0\\] is 1000000000 \\(a whole number of rows from 0 to the [0-9]+ columns of /timeseries\\)"
  "rows_many|rows_many.h5|'rows_many.h5' is damaged: /replicas/rows_written\\[0\\] is 1000000000 \\(from 0 to its n_samples, [0-9]+\\)"
  "spec_text_bad|spec_text_bad.h5|'spec_text_bad.h5' is damaged: its stored campaign \\(attribute spec_text, a copy of '.*other_campaign.toml'\\) does not parse \\(line 3:[0-9]+: malformed TOML"
  "spec_text_other|spec_text_other.h5|'spec_text_other.h5' is damaged: its stored campaign \\(attribute spec_text\\) is not the campaign of its spec_fingerprint"
  "model_edited|model_edited.h5|'model_edited.h5' is damaged: its attribute model is \"XYZ\" where its stored campaign says \"RD0\""
  "phi_edited|phi_edited.h5|'phi_edited.h5' is damaged: /replicas/phi\\[0\\] is 0.5 where its stored campaign says 0.8"
  "no_seed|no_seed.h5|'no_seed.h5' is damaged: it has no /replicas/seed, which its campaign has"
  "box_side_text|box_side_text.h5|'box_side_text.h5' is damaged: /final/box_side is not floating-point numbers"
  "progress_high|progress_high.h5|'progress_high.h5' is damaged: /replicas/progress\\[0\\] is 5 \\(the fraction of its steps done, from 0 to 1\\)"
  "rank_negative|rank_negative.h5|'rank_negative.h5' is damaged: /replicas/rank\\[0\\] is -3 \\(the MPI rank that ran it, from 0, or -1 before it runs\\)"
  "evaluations_negative|evaluations_negative.h5|'evaluations_negative.h5' is damaged: /replicas/force_evaluations\\[0\\] is -1 \\(a whole count from 0\\)"
  "ranks_negative|ranks_negative.h5|'ranks_negative.h5' is damaged: its attribute n_ranks is -3 \\(the ranks of its last run, from 0 to 2\\^20\\)"
  "created_text|created_text.h5|'created_text.h5' is damaged: its attribute created is 'not a date' \\(a UTC time such as 2026-11-29T09:01:35Z\\)"
  "no_cost|no_cost.h5|'no_cost.h5' is damaged: it has no /replicas/estimated_cost"
  "status_float|status_float.h5|'status_float.h5' is damaged: /replicas/status is not integers \\(jamsim writes it so\\)")
foreach(kind IN LISTS bad_kinds)
  jamsim_row_fields("${kind}" name file regex)
  add_test(NAME archive_file.status_${name}
    COMMAND ${expect} "^jamsim status: ${regex}" ${bad_dir}/none.h5 $<TARGET_FILE:jamsim> status ${file}
    WORKING_DIRECTORY ${bad_dir})
  add_test(NAME archive_file.merge_shard_${name}
    COMMAND ${expect} "^jamsim merge: shard ${regex}" ${bad_dir}/merged.h5 $<TARGET_FILE:jamsim> merge merged.h5 good.h5 ${file}
    WORKING_DIRECTORY ${bad_dir})
  set(tests archive_file.status_${name} archive_file.merge_shard_${name})
  if(NOT name STREQUAL "missing" AND NOT name STREQUAL "directory")  # run creates a missing archive
    add_test(NAME archive_file.run_${name}
      COMMAND ${expect} "other_campaign.toml: refusing to use the archive: ${regex}" ${bad_dir}/none.h5 $<TARGET_FILE:jamsim> run ${campaigns}/other_campaign.toml -o ${file}
      WORKING_DIRECTORY ${bad_dir})
    add_test(NAME archive_file.merge_into_${name}
      COMMAND ${expect} "^jamsim merge: refusing the output: ${regex}" ${bad_dir}/none.h5 $<TARGET_FILE:jamsim> merge ${file} good.h5
      WORKING_DIRECTORY ${bad_dir})
    list(APPEND tests archive_file.run_${name} archive_file.merge_into_${name})
  endif()
  # An HDF5 file as a replica's starting state (the others go to the LAMMPS reader).
  if(NOT name MATCHES "^(missing|directory|empty|not_hdf5)$")
    add_test(NAME archive_file.initial_${name}
      COMMAND ${expect} "^jamsim replica: --initial = ${file} is not allowed: a jamsim campaign archive or a LAMMPS data file: ${regex}"
        ${bad_dir}/q.h5 $<TARGET_FILE:jamsim> replica --N 16 --phi 0.8 --rate 1e-2 --strain 0.01 --initial ${file} -o q.h5
      WORKING_DIRECTORY ${bad_dir})
    list(APPEND tests archive_file.initial_${name})
  endif()
  set_tests_properties(${tests} PROPERTIES LABELS unit FIXTURES_REQUIRED bad_archives RESOURCE_LOCK bad_archives
    ENVIRONMENT "EXPECT_STATUS=2;PROTECT=${file} good.h5")
endforeach()
# A merge's output in a folder that does not exist, or under a file: refused in words (it
# said "cannot open the lock file").
foreach(case "nofolder|no_such_folder/m.h5|'no_such_folder' does not exist" "under_file|good.h5/m.h5|'good.h5' is not a folder")
  string(REPLACE "|" ";" fields "${case}")
  list(GET fields 0 name)
  list(GET fields 1 file)
  list(GET fields 2 why)
  add_test(NAME archive_file.merge_output_${name}
    COMMAND ${expect} "^jamsim merge: refusing the output '${file}': a file in an existing folder \\(${why}\\)"
      ${bad_dir}/no_such_folder $<TARGET_FILE:jamsim> merge ${file} good.h5
    WORKING_DIRECTORY ${bad_dir})
  set_tests_properties(archive_file.merge_output_${name} PROPERTIES LABELS unit FIXTURES_REQUIRED bad_archives
    RESOURCE_LOCK bad_archives ENVIRONMENT "EXPECT_STATUS=2;PROTECT=good.h5")
endforeach()
# An output named with white space at an end (-o ' ': HDF5's create failed without a reason,
# and replica wrote a file named ' '), and one through a symbolic link into a folder that does
# not exist (the same failure): refused before any work.
jamsim_cli_error(run_output_blank "-o \" \" is not allowed: a file name that neither starts nor ends with white space"
  run ${campaigns}/other_campaign.toml -o " ")
jamsim_cli_error(replica_output_spaced "--output =  x.h5 is not allowed: a file name that neither starts nor ends with white space"
  replica --N 16 -o " x.h5")
add_test(NAME cli.run_output_dangling_link
  COMMAND bash -c "ln -sfn /nonexistent-jamsim-folder/x.h5 dangling.h5 && exec \"$0\" \"$@\"" ${expect}
    "-o \"dangling.h5\" is not allowed: a file that can be made: 'dangling.h5' is a symbolic link to '/nonexistent-jamsim-folder/x.h5', whose folder '/nonexistent-jamsim-folder' does not exist"
    ${out} $<TARGET_FILE:jamsim> run ${campaigns}/other_campaign.toml -o dangling.h5
  WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
set_tests_properties(cli.run_output_dangling_link PROPERTIES LABELS unit ENVIRONMENT "EXPECT_STATUS=2")
# A run on a directory says so too (a file path is needed).
add_test(NAME archive_file.run_directory
  COMMAND ${expect} "-o \"a_directory\" is not allowed: a file path, not a directory" ${bad_dir}/none.h5 $<TARGET_FILE:jamsim> run ${campaigns}/other_campaign.toml -o a_directory
  WORKING_DIRECTORY ${bad_dir})
# The good archive passes, and a finished one says it is complete.
add_test(NAME archive_file.status_good
  COMMAND bash -c "$<TARGET_FILE:jamsim> status good.h5 | grep -q 'finished .* (complete: every replica is finished)'"
  WORKING_DIRECTORY ${bad_dir})
set_tests_properties(archive_file.run_directory archive_file.status_good PROPERTIES LABELS unit FIXTURES_REQUIRED bad_archives
  RESOURCE_LOCK bad_archives ENVIRONMENT "EXPECT_STATUS=2;PROTECT=good.h5")
# The same shard twice (here through another path) is refused: it said "merged 1 replicas from
# 2 archives".
add_test(NAME archive_file.merge_shard_twice
  COMMAND ${expect} "^jamsim merge: shard './good.h5' is given twice \\(as 'good.h5' too\\): name each shard once" ${bad_dir}/merged.h5
    $<TARGET_FILE:jamsim> merge merged.h5 good.h5 ./good.h5
  WORKING_DIRECTORY ${bad_dir})
set_tests_properties(archive_file.merge_shard_twice PROPERTIES LABELS unit FIXTURES_REQUIRED bad_archives
  RESOURCE_LOCK bad_archives ENVIRONMENT "EXPECT_STATUS=2;PROTECT=good.h5")
# The output as an input under another spelling: refused as the same spelling is (it merged
# into the input, writing its `merged` stamp there).
add_test(NAME archive_file.merge_into_input_spelled_otherwise
  COMMAND ${expect} "^jamsim merge: 'good.h5' is both the output and an input \\('./good.h5'\\): name a new output"
    ${bad_dir}/none.h5 $<TARGET_FILE:jamsim> merge ./good.h5 good.h5
  WORKING_DIRECTORY ${bad_dir})
set_tests_properties(archive_file.merge_into_input_spelled_otherwise PROPERTIES LABELS unit FIXTURES_REQUIRED bad_archives
  RESOURCE_LOCK bad_archives ENVIRONMENT "EXPECT_STATUS=2;PROTECT=good.h5")
# An archive whose creation a kill interrupted (no HDF5 signature yet, its creation marker
# beside it, as mpi.kill_loop_resumes_from_checkpoints met it): status says so, and a run or
# a merge to it makes it anew (it was refused as "not an HDF5 file" for good).
add_test(NAME archive_file.interrupted_creation
  COMMAND bash -c "set -e; rm -rf half.h5*; head -c 4096 /dev/zero > half.h5; touch half.h5.creating; ! $<TARGET_FILE:jamsim> status half.h5 2> half.txt; grep -q \"'half.h5' is being created, or a kill interrupted its creation\" half.txt; $<TARGET_FILE:jamsim> run ${campaigns}/other_campaign.toml -o half.h5 > /dev/null 2>&1; test ! -e half.h5.creating; $<TARGET_FILE:jamsim> status half.h5 | grep -q '1/1 done'; head -c 4096 /dev/zero > merged_half.h5; touch merged_half.h5.creating; $<TARGET_FILE:jamsim> merge merged_half.h5 half.h5 > /dev/null; test ! -e merged_half.h5.creating; $<TARGET_FILE:jamsim> status merged_half.h5 | grep -q '1/1 done'"
  WORKING_DIRECTORY ${campaign_dir})
set_tests_properties(archive_file.interrupted_creation PROPERTIES LABELS unit)
# Outputs that name no writable file: a path ending in '/' (a folder was made, then an MPI
# abort), a loop of symbolic links (an uncaught filesystem error and a leftover lock), a
# read-only archive (written anyway by root, an HDF5 abort otherwise). Refused by run and
# merge before any work, nothing left behind.
add_test(NAME archive_file.output_not_a_file
  COMMAND bash -c "set -e; rm -rf ro.h5 ro.h5.lock loop.h5 loop.h5.lock slash; $<TARGET_FILE:jamsim> run ${campaigns}/other_campaign.toml -o ro.h5 > /dev/null 2>&1; chmod 444 ro.h5; ln -s loop.h5 loop.h5; for o in slash/ slash/. loop.h5 ro.h5; do ! $<TARGET_FILE:jamsim> run ${campaigns}/other_campaign.toml -o $o 2> run.txt; cat run.txt; grep -q -e \"-o .$o. is not allowed: \" run.txt; ! $<TARGET_FILE:jamsim> merge $o good.h5 2> merge.txt; cat merge.txt; grep -q '^jamsim merge: refusing the output: ' merge.txt; done; grep -q 'read-only (mode 0444)' run.txt; test ! -e slash -a ! -e ro.h5.lock -a ! -e loop.h5.lock; ! grep -q MPI_ABORT run.txt merge.txt"
  WORKING_DIRECTORY ${bad_dir})
set_tests_properties(archive_file.output_not_a_file PROPERTIES LABELS unit FIXTURES_REQUIRED bad_archives
  RESOURCE_LOCK bad_archives)
# LAMMPS data files whose tilt or atoms cannot be folded into the cell (lammps_out_of_reach.sh).
add_test(NAME archive_file.lammps_data_out_of_reach
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/lammps_out_of_reach.sh $<TARGET_FILE:jamsim>
  WORKING_DIRECTORY ${bad_dir})
set_tests_properties(archive_file.lammps_data_out_of_reach PROPERTIES LABELS unit FIXTURES_REQUIRED bad_archives
  RESOURCE_LOCK bad_archives)
# A refused merge output leaves no lock file beside it.
add_test(NAME archive_file.refused_merge_leaves_no_lock
  COMMAND bash -c "rm -f text.h5.lock; ! $<TARGET_FILE:jamsim> merge text.h5 good.h5 2> refused.txt && grep -q 'refusing the output' refused.txt && test ! -e text.h5.lock"
  WORKING_DIRECTORY ${bad_dir})
set_tests_properties(archive_file.refused_merge_leaves_no_lock PROPERTIES LABELS unit FIXTURES_REQUIRED bad_archives
  RESOURCE_LOCK bad_archives)
# An archive on which HDF5 loops for ever (a global heap's objects zeroed): every reader gives
# up after the read deadline (2 s here) with one message, exit 2, changing nothing (they spun
# until killed, and jamsim run ignored SIGTERM meanwhile).
set(heap_message "^jamsim: reading 'heap_[a-z]+.h5' did not finish within 2 s: its HDF5 structure is damaged")
set(heap_commands
  "status_last|status heap_last.h5"
  "run_last|run ${campaigns}/other_campaign.toml -o heap_last.h5"
  "status|status heap_zeroed.h5"
  "run|run ${campaigns}/other_campaign.toml -o heap_zeroed.h5"
  "merge_shard|merge -o merged.h5 good.h5 heap_zeroed.h5"
  "merge_into|merge heap_zeroed.h5 good.h5"
  "export|export heap_zeroed.h5 -r 0 -o merged.h5"
  "initial|replica --N 16 --phi 0.8 --rate 1e-2 --strain 0.01 --initial heap_zeroed.h5 -o merged.h5")
foreach(row IN LISTS heap_commands)
  jamsim_row_fields("${row}" name command)
  separate_arguments(command)
  add_test(NAME archive_file.heap_zeroed_${name}
    COMMAND ${expect} "${heap_message}" ${bad_dir}/merged.h5 $<TARGET_FILE:jamsim> ${command}
    WORKING_DIRECTORY ${bad_dir})
  set_tests_properties(archive_file.heap_zeroed_${name} PROPERTIES LABELS unit FIXTURES_REQUIRED bad_archives
    RESOURCE_LOCK bad_archives TIMEOUT 60
    ENVIRONMENT "EXPECT_STATUS=2;PROTECT=heap_zeroed.h5 heap_last.h5 good.h5;JAMSIM_READ_DEADLINE_SECONDS=2")
endforeach()
# A file the user keeps under OUTPUT.tmp survives the commands that write OUTPUT (they wrote
# through that name and renamed it away): export, minimize --lammps-data, replica -o. The
# outputs have a new file's mode (0644 under umask 022), not the temporary name's 0600.
add_test(NAME archive_file.user_tmp_file_kept
  COMMAND bash -c "set -e; umask 022; rm -rf keep*; for f in keep.data.tmp keep_min.data.tmp keep.h5.tmp; do echo precious > $f; done; $<TARGET_FILE:jamsim> export good.h5 -r 0 -o keep.data > /dev/null; $<TARGET_FILE:jamsim> minimize --N 64 --lammps-data keep_min.data > /dev/null; $<TARGET_FILE:jamsim> replica --N 16 --phi 0.8 --rate 1e-2 --strain 0.01 -o keep.h5 > /dev/null 2>&1; for f in keep.data.tmp keep_min.data.tmp keep.h5.tmp; do grep -qx precious $f; done; test -s keep.data -a -s keep_min.data -a -s keep.h5; test -z \"$(ls keep*.??????.tmp 2> /dev/null)\"; test \"$(stat -c %a keep.data keep_min.data keep.h5 | sort -u)\" = 644"
  WORKING_DIRECTORY ${bad_dir})
set_tests_properties(archive_file.user_tmp_file_kept PROPERTIES LABELS unit FIXTURES_REQUIRED bad_archives
  RESOURCE_LOCK bad_archives)
# A merge whose input cannot be read midway (an open that fails after the checks, by the
# LD_PRELOAD wrapper of the fault cases) leaves no lock: a new output is removed, an existing
# one keeps what it held, and the same merge then completes it. (It left OUTPUT.lock and a
# half-made output that status called an interrupted run.)
set(fail_input "OMPI_COMM_WORLD_RANK=0 FAIL_OPEN_RANK=0 FAIL_OPEN_SUFFIX=fm0.h5 FAIL_OPEN_AFTER=4 LD_PRELOAD=$<TARGET_FILE:jamsim_fail_open>")
add_test(NAME archive_file.merge_failed_midway
  COMMAND bash -c "set -e; rm -rf fm*; $<TARGET_FILE:jamsim> run ${campaigns}/other_campaign.toml --shard 0/2 -o fm0.h5 > /dev/null 2>&1; $<TARGET_FILE:jamsim> run ${campaigns}/other_campaign.toml --shard 1/2 -o fm1.h5 > /dev/null 2>&1; ! env ${fail_input} $<TARGET_FILE:jamsim> merge fmn.h5 fm0.h5 fm1.h5 2> new.txt; cat new.txt; grep -q \"^jamsim merge: merging into 'fmn.h5' failed: .*; the new 'fmn.h5' was removed\" new.txt; test ! -e fmn.h5 -a ! -e fmn.h5.lock -a ! -e fmn.h5.creating; cp fm1.h5 fme.h5; ! env ${fail_input} $<TARGET_FILE:jamsim> merge fme.h5 fm0.h5 2> old.txt; cat old.txt; grep -q \"; 'fme.h5' keeps what it held and the 0 replicas this merge copied whole before the failure: run the same merge again\" old.txt; test ! -e fme.h5.lock; $<TARGET_FILE:jamsim> status fme.h5 | grep -q '0/1 done'; $<TARGET_FILE:jamsim> merge fme.h5 fm0.h5 | grep -q '1/1 done'"
  WORKING_DIRECTORY ${bad_dir})
set_tests_properties(archive_file.merge_failed_midway PROPERTIES LABELS unit FIXTURES_REQUIRED bad_archives
  RESOURCE_LOCK bad_archives)
# A merged archive is complete, not "(running or interrupted)".
add_test(NAME archive_file.merged_is_complete
  COMMAND bash -c "rm -rf m0.h5* m1.h5* merged_whole.h5*; $<TARGET_FILE:jamsim> run ${campaigns}/other_campaign.toml --shard 0/2 -o m0.h5 > /dev/null 2>&1 && $<TARGET_FILE:jamsim> run ${campaigns}/other_campaign.toml --shard 1/2 -o m1.h5 > /dev/null 2>&1 && $<TARGET_FILE:jamsim> merge merged_whole.h5 m0.h5 m1.h5 > merge.txt && grep -q 'finished - (complete: every replica is finished. merged 20' merge.txt && ! grep -q 'running or interrupted' merge.txt"
  WORKING_DIRECTORY ${campaign_dir})
# Seeds that a LAMMPS data file as [run] initial makes the same bits, and initial_match = "id"
# with such a file, are refused (data_initial_seeds.sh).
add_test(NAME cli.data_initial_seeds
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/data_initial_seeds.sh $<TARGET_FILE:jamsim>
  WORKING_DIRECTORY ${bad_dir})
set_tests_properties(cli.data_initial_seeds PROPERTIES LABELS unit)
# What an extension killed before its rename left beside the archive is removed, with a note,
# by the next run (stale_extension.sh).
add_test(NAME cli.stale_extension
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/stale_extension.sh $<TARGET_FILE:jamsim>
  WORKING_DIRECTORY ${bad_dir})
set_tests_properties(cli.stale_extension PROPERTIES LABELS unit)
# A singleton killed by SIGKILL leaves its Open MPI session folder (jamsim-mpi.XXXXXX under
# TMPDIR); the next jamsim removes it, and never a live one's (session_folders.sh).
add_test(NAME cli.session_folders
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/session_folders.sh $<TARGET_FILE:jamsim>
  WORKING_DIRECTORY ${bad_dir})
set_tests_properties(cli.session_folders PROPERTIES LABELS unit)
# A shard past the campaign's replicas says that it holds none (it made an empty archive
# without a word); a shard with one says nothing of the kind.
add_test(NAME cli.shard_without_replicas
  COMMAND bash -c "rm -rf es*.h5*; $<TARGET_FILE:jamsim> run ${campaigns}/other_campaign.toml --shard 1/2 -o es1.h5 > es1.txt 2>&1 && grep -q '^shard 1/2 holds no replica: the campaign has 1 replica, in shards 0 to 0; this shard.s archive holds them all pending, for jamsim merge' es1.txt && $<TARGET_FILE:jamsim> run ${campaigns}/other_campaign.toml --shard 0/2 -o es0.h5 > es0.txt 2>&1 && ! grep -q 'holds no replica' es0.txt"
  WORKING_DIRECTORY ${campaign_dir})
set_tests_properties(cli.shard_without_replicas PROPERTIES LABELS unit)

# The deadline variables (JAMSIM_READ_DEADLINE_SECONDS, JAMSIM_WRITE_DEADLINE_SECONDS) refused
# in words when they are not a number of seconds.
add_test(NAME cli.deadline_variables_refused
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/deadline_variables.sh $<TARGET_FILE:jamsim>)
set_tests_properties(cli.deadline_variables_refused PROPERTIES LABELS unit)

