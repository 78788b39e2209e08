#!/usr/bin/env bash
# The analysis package as installed by `cmake --install BUILD --component python --prefix P`
# (tools/install/JamsimInstall.cmake, tools/pyproject.toml), used from a folder outside the
# source tree with nothing of the checkout on PATH or PYTHONPATH:
#   - bin/ holds exactly the commands of pyproject.toml's [project.scripts], and no others;
#   - each answers --help with a usage naming itself (jamsim-report also through a symbolic link),
#     and refuses a missing archive with exit status 2 and one message naming it;
#   - `import jamsim_analysis` with PYTHONPATH=P/lib/python3/dist-packages (as tools/README.md
#     says) loads the installed copy, with every module of the source package;
#   - tools/pyproject.toml builds a wheel with setuptools alone (no pip) whose entry points
#     are the same commands and whose files are the package's modules;
#   - no installed file names the source or build tree.
# usage: install_package.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$(cd "$1" && pwd -P) src=$(cd "$2" && pwd -P)
python=/usr/bin/python3
work=$(mktemp -d "${TMPDIR:-/tmp}/jamsim-pyinstall.XXXXXX")
fail() { echo "FAIL: $*" >&2; echo "(left in $work)" >&2; exit 1; }
case "$work/" in "$src"/* | "$build"/*) fail "the temporary directory $work is inside the source tree" ;; esac
prefix=$work/prefix
cmake --install "$build" --component python --prefix "$prefix" > "$work/install.log" ||
  { cat "$work/install.log"; fail "cmake --install --component python"; }
pydir=$prefix/lib/python3/dist-packages
[[ -f $pydir/jamsim_analysis/__init__.py ]] || fail "no package at $pydir/jamsim_analysis"

clean_env=(env -i HOME="$work" PATH="$prefix/bin:/usr/bin:/bin" LANG=C.UTF-8 MPLBACKEND=Agg)
mkdir "$work/run"
cd "$work/run"

# The commands of pyproject.toml, as the wrappers' names.
"$python" - "$src/tools/pyproject.toml" > commands.txt <<'EOF'
import sys, tomllib
for name, target in sorted(tomllib.load(open(sys.argv[1], "rb"))["project"]["scripts"].items()):
    print(name, target)
EOF
[[ $(wc -l < commands.txt) -ge 6 ]] || { cat commands.txt; fail "pyproject.toml names fewer than 6 commands"; }
diff <(cut -d' ' -f1 commands.txt) <(ls "$prefix/bin" | sort) ||
  fail "bin/ does not hold exactly the commands of pyproject.toml's [project.scripts]"

mkdir "$work/elsewhere"
while read -r name target; do
  "${clean_env[@]}" "$name" --help > help.txt 2> help.err || { cat help.err; fail "$name --help"; }
  grep -q "^usage: $name " help.txt || { cat help.txt; fail "$name --help does not give its usage as '$name'"; }
  [[ ! -s help.err ]] || { cat help.err; fail "$name --help wrote to stderr"; }
  # a missing archive: exit status 2 and one line naming it (no traceback)
  case $name in
    jamsim-analyze) args=(summary missing.h5) ;;
    jamsim-transient-length) args=(missing.h5) ;;
    jamsim-plot-replica) args=(missing.h5 out.png) ;;
    *) args=(missing.h5 out) ;;
  esac
  set +e
  "${clean_env[@]}" "$name" "${args[@]}" > bad.out 2> bad.err
  rc=$?
  set -e
  [[ $rc -eq 2 ]] || { cat bad.err; fail "$name ${args[*]}: exit status $rc, not 2"; }
  grep -q "missing.h5" bad.err && ! grep -q Traceback bad.err || { cat bad.err; fail "$name: no plain message naming missing.h5"; }
  echo "$name ($target): --help and a missing archive as expected"
done < commands.txt
# through a symbolic link in another folder (the wrapper finds the package from its target)
ln -s "$prefix/bin/jamsim-report" "$work/elsewhere/report"
"${clean_env[@]}" "$work/elsewhere/report" --help | grep -q "^usage: jamsim-report " || fail "jamsim-report through a symbolic link"

# The package from the prefix, with the PYTHONPATH that tools/README.md gives.
"${clean_env[@]}" PYTHONPATH="$pydir" "$python" - "$pydir" "$src/tools/jamsim_analysis" <<'EOF' || fail "import from $pydir"
import os, sys
import jamsim_analysis, jamsim_analysis.cli, jamsim_analysis.scripts.plot_campaign
installed, source = sys.argv[1:3]
where = os.path.dirname(jamsim_analysis.__file__)
assert where == os.path.join(installed, "jamsim_analysis"), where
have = {os.path.relpath(os.path.join(d, f), where) for d, _, fs in os.walk(where) for f in fs if f.endswith(".py")}
want = {os.path.relpath(os.path.join(d, f), source) for d, _, fs in os.walk(source) for f in fs if f.endswith(".py")}
assert have == want, (sorted(want - have), sorted(have - want))
assert callable(jamsim_analysis.fit_collapse) and callable(jamsim_analysis.open_archives)
print(f"import jamsim_analysis: {where} ({len(have)} modules)")
EOF

# pyproject.toml with setuptools alone: a wheel from a copy of the package (the build writes
# next to its input), its entry points and files.
mkdir "$work/wheel"
cp "$src/tools/pyproject.toml" "$work/wheel/"
cp -r "$src/tools/jamsim_analysis" "$work/wheel/"
find "$work/wheel" -name __pycache__ -prune -exec rm -rf {} +
(cd "$work/wheel" && "$python" -c "from setuptools import build_meta; print(build_meta.build_wheel('dist'))") \
  > wheel.log 2>&1 || { cat wheel.log; fail "setuptools cannot build a wheel from tools/pyproject.toml"; }
"$python" - "$work"/wheel/dist/*.whl commands.txt "$src/tools/jamsim_analysis" <<'EOF' || fail "the wheel"
import configparser, os, sys, zipfile
wheel, commands, source = sys.argv[1:4]
z = zipfile.ZipFile(wheel)
entry = [n for n in z.namelist() if n.endswith(".dist-info/entry_points.txt")]
cp = configparser.ConfigParser()
cp.read_string(z.read(entry[0]).decode())
got = {k: v for k, v in cp["console_scripts"].items()}
want = dict(line.split() for line in open(commands))
assert got == want, (got, want)
have = {n for n in z.namelist() if n.endswith(".py")}
files = {os.path.join("jamsim_analysis", os.path.relpath(os.path.join(d, f), source))
         for d, _, fs in os.walk(source) for f in fs if f.endswith(".py")}
assert have == files, (sorted(files - have), sorted(have - files))
print(f"wheel {os.path.basename(wheel)}: {len(got)} commands, {len(have)} modules")
EOF

if grep -rIl -e "$src" -e "$build" "$prefix"; then fail "installed files name the source or build tree"; fi
echo "installed package check passed"
rm -rf "$work"
