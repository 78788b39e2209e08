#!/usr/bin/env bash
# `cmake --install` into a temporary prefix, then use only what it installed, from a working
# directory outside the source tree, with no checkout on PATH:
#   - jamsim --version equals the build tree's; --help lists every subcommand;
#   - a small campaign on 2 ranks (mpiexec), its status, the Python commands (bin/jamsim-analyze,
#     also through a symbolic link elsewhere, jamsim-plot-campaign, jamsim-transient-length),
#     the package imported from PREFIX/lib/python3/dist-packages, an export of a final configuration;
#   - every installed campaign passes the dry run;
#   - the installed Slurm script hands the installed jamsim to its jobs (a stand-in sbatch
#     records what it was given), with no jamsim on PATH and no JAMSIM set;
#   - the Tcl modulefile puts the installed bin/ and Python package on the paths;
#   - no installed text file names the source or build tree.
# usage: install_prefix.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$(cd "$1" && pwd -P) src=$(cd "$2" && pwd -P)
mpiexec=${MPIEXEC:-mpiexec}
work=$(mktemp -d "${TMPDIR:-/tmp}/jamsim-install.XXXXXX")
fail() { echo "FAIL: $*" >&2; echo "(left in $work)" >&2; exit 1; }
case "$work/" in "$src"/* | "$build"/*) fail "the temporary directory $work is inside the source tree" ;; esac
prefix=$work/prefix
cmake --install "$build" --prefix "$prefix" > "$work/install.log" || { cat "$work/install.log"; fail "cmake --install"; }

# A clean environment: the prefix and the system, nothing of the checkout or the build.
clean_env=(env -i HOME="$work" PATH="$prefix/bin:/usr/bin:/bin" LANG=C.UTF-8 MPLBACKEND=Agg
           OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
           OMPI_MCA_btl_vader_single_copy_mechanism=none OMPI_MCA_mpi_yield_when_idle=1)
mkdir "$work/run"
cd "$work/run"

[[ $("${clean_env[@]}" which jamsim) == "$prefix/bin/jamsim" ]] || fail "jamsim on PATH is not the installed one"
version=$("${clean_env[@]}" jamsim --version)
[[ $version == "$("$build/jamsim" --version)" && $version == "jamsim "* ]] || fail "jamsim --version: '$version'"
"${clean_env[@]}" jamsim --help > help.txt
for sub in replica run status merge export minimize parameters models; do
  grep -qE "^  $sub +[A-Z]" help.txt || fail "jamsim --help does not list '$sub'"
done

cat > tiny.toml <<'EOF'
[campaign]
name = "install-check"
output = "tiny.h5"
[run]
strain = 0.05
sample_interval = 0.01
[sweep]
N = [64]
phi = [0.86]
rate = [1e-3]
seeds = 2
EOF
"${clean_env[@]}" timeout 300 "$mpiexec" -n 2 jamsim run tiny.toml > run.log 2>&1 || { cat run.log; fail "jamsim run on 2 ranks"; }
"${clean_env[@]}" jamsim status tiny.h5 | tee status.txt
grep -q '2/2 done' status.txt || fail "the campaign did not finish"
[[ $(h5dump -a /code_version tiny.h5 | grep -c "${version#jamsim }") -ge 1 ]] || fail "code_version in the archive is not '${version#jamsim }'"

# A Python tool from bin/, and through a link in another folder (it finds its package).
"${clean_env[@]}" jamsim-analyze summary tiny.h5 > summary.txt || fail "jamsim-analyze summary"
grep -q "RD0" summary.txt || { cat summary.txt; fail "jamsim-analyze summary printed no RD0 replica"; }
mkdir "$work/elsewhere"
ln -s "$prefix/bin/jamsim-analyze" "$work/elsewhere/ja"
"${clean_env[@]}" "$work/elsewhere/ja" summary tiny.h5 > /dev/null || fail "jamsim-analyze through a link"
# The other installed commands of the package on the same archive, and the package itself
# from the documented PYTHONPATH (tools/README.md, "Installing the package").
"${clean_env[@]}" jamsim-plot-campaign tiny.h5 figs > /dev/null || fail "jamsim-plot-campaign"
[[ -s figs/flow_curves.png ]] || fail "jamsim-plot-campaign drew no figs/flow_curves.png"
"${clean_env[@]}" jamsim-transient-length tiny.h5 | grep -q "0.860" || fail "jamsim-transient-length"
"${clean_env[@]}" PYTHONPATH="$prefix/lib/python3/dist-packages" /usr/bin/python3 -c \
  "import jamsim_analysis as ja; print(ja.__file__); print(len(ja.open_archives('tiny.h5').replicas))" > import.txt ||
  fail "import jamsim_analysis with PYTHONPATH=$prefix/lib/python3/dist-packages"
[[ $(sed -n 1p import.txt) == "$prefix/lib/python3/dist-packages/jamsim_analysis/__init__.py" && $(sed -n 2p import.txt) == 2 ]] ||
  { cat import.txt; fail "jamsim_analysis was not imported from the prefix or did not read tiny.h5"; }
"${clean_env[@]}" jamsim export tiny.h5 --replica 1 -o replica_1.data > /dev/null || fail "jamsim export"
grep -q "^64 atoms" replica_1.data || fail "the exported data file has no '64 atoms'"

# Every installed campaign is understood by the installed jamsim.
for c in "$prefix"/share/jamsim/campaigns/*.toml "$prefix"/share/jamsim/campaigns/*/*.toml; do
  [[ -e $c ]] || continue
  "${clean_env[@]}" jamsim run --dry-run --no-calibrate "$c" -o "$work/dry.h5" > dry.log 2>&1 ||
    { cat dry.log; fail "dry run of installed campaign $c"; }
done
[[ ! -e $work/dry.h5 ]] || fail "a dry run wrote an archive"

# The installed Slurm script: no JAMSIM, no jamsim on PATH, a stand-in sbatch.
mkdir "$work/fakebin"
cat > "$work/fakebin/sbatch" <<EOF
#!/bin/sh
echo "\$@" >> "$work/sbatch.log"
echo 4242
EOF
chmod +x "$work/fakebin/sbatch"
env -i HOME="$work" PATH="$work/fakebin:/usr/bin:/bin" OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 \
  "$prefix/share/jamsim/slurm/submit_campaign.sh" tiny.toml "$work/run/merged.h5" 2 > submit.log 2>&1 ||
  { cat submit.log; fail "installed submit_campaign.sh"; }
grep -q "JAMSIM=$prefix/bin/jamsim" "$work/sbatch.log" || { cat "$work/sbatch.log"; fail "the jobs were not handed the installed jamsim"; }
grep -q "$prefix/share/jamsim/slurm/campaign_array.sbatch" "$work/sbatch.log" || fail "the array job is not the installed script"

# The Tcl modulefile, read by tclsh with the module commands stubbed.
modulefile=$prefix/share/jamsim/modulefiles/jamsim/$(sed -n 's/^project(jamsim VERSION \([0-9.]*\).*/\1/p' "$src/CMakeLists.txt")
[[ -f $modulefile && -f $modulefile.lua ]] || fail "no modulefiles $modulefile{,.lua}"
if command -v tclsh > /dev/null; then
  tclsh > module.txt <<EOF
proc module-whatis {args} {}
proc prereq {args} {}
proc setenv {var value} { puts "setenv \$var \$value" }
proc prepend-path {var value} { puts "prepend \$var \$value" }
source {$modulefile}
EOF
  grep -qx "prepend PATH $prefix/bin" module.txt || { cat module.txt; fail "the modulefile does not put $prefix/bin on PATH"; }
  pydir=$(sed -n 's/^prepend PYTHONPATH //p' module.txt)
  [[ -f $pydir/jamsim_analysis/__init__.py ]] || fail "the modulefile's PYTHONPATH '$pydir' has no jamsim_analysis"
  grep -qx "setenv JAMSIM $prefix/bin/jamsim" module.txt || fail "the modulefile does not set JAMSIM"
  "${clean_env[@]}" PYTHONPATH="$pydir" /usr/bin/python3 -c "import jamsim_analysis" || fail "import jamsim_analysis from $pydir"
else
  echo "note: no tclsh, the Tcl modulefile is not read"
fi

# Nothing installed names the checkout or the build tree.
if grep -rIl -e "$src" -e "$build" "$prefix"; then fail "installed files name the source or build tree"; fi
echo "install check passed: $prefix"
rm -rf "$work"
