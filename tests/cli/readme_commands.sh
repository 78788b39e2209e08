#!/usr/bin/env bash
# The README's command table ("Commands") lists exactly the subcommands of `jamsim --help`.
# usage: readme_commands.sh JAMSIM README
set -euo pipefail
jamsim=$1 readme=$2
subs=$("$jamsim" --help | sed -n '/^Subcommands:/,$p' | awk 'NR > 1 && NF { print $1 }')
[[ -n $subs ]] || { echo "FAIL: jamsim --help lists no subcommands"; exit 1; }
listed=$(sed -n 's/^| `jamsim \([a-z]*\)` | .*/\1/p' "$readme")
if [[ $(sort <<<"$subs") != $(sort <<<"$listed") ]]; then
  echo "FAIL: jamsim --help has: $(echo $subs); the README's command table has: $(echo $listed)"
  exit 1
fi
"$jamsim" --version | grep -qE '^jamsim [0-9]+\.[0-9]+\.[0-9]+' || { echo "FAIL: jamsim --version"; exit 1; }
echo "README lists the $(wc -w <<<"$subs") subcommands of jamsim --help"
