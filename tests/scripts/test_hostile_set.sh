#!/usr/bin/env bash
# The kept hostile set (tests/hostile/cases): each input refused with its exit status and one
# line on stderr, no byte a terminal acts on, within 10 s (a hang fails); nothing written through
# a planted link, and no run directory left by a run refused before it measured. A case runs
# heightmarch, or heightmarch-bench where its first word says so. The set is copied first: a
# command may write into a run it refuses (.lock). About 20 s of CPU.
# Usage: test_hostile_set.sh BUILD_DIR
set -euo pipefail
source "$(dirname "$0")/prelude.sh"
build="$(cd "${1:?usage: test_hostile_set.sh BUILD_DIR}" && pwd)"
cp -r "$root/tests/hostile" "$tmp/set"
set_dir="$tmp/set"
mkfifo "$tmp/fifo.png" "$tmp/fifo.csv"
mkdir -p "$tmp/elsewhere" "$tmp/linked-out"
ln -s "$tmp/elsewhere" "$tmp/linked-out/gallery"
esc=$'\e]0;PWN\a\e[2J\xc2\x9b'
# C0 controls but tab and newline, DEL, C1 controls (UTF-8), bidirectional overrides and isolates
acts_on_terminal=$'[\x01-\x08\x0b-\x1f\x7f]|\xc2[\x80-\x9f]|\xe2\x80[\xaa-\xae]|\xe2\x81[\xa6-\xa9]'
failed=0 cases=0
while read -r expect line; do
  [[ -z "$expect" || "$expect" == \#* ]] && continue
  read -ra words <<<"$line"
  args=()
  for w in "${words[@]}"; do
    w="${w//@/$set_dir}" w="${w//\{tmp\}/$tmp}"
    args+=("${w//\{esc\}/$esc}")
  done
  cases=$((cases + 1))
  program="heightmarch"
  if [[ "${args[0]}" == heightmarch-bench ]]; then program="heightmarch-bench" args=("${args[@]:1}"); fi
  status=0
  (cd "$tmp" && exec timeout -s KILL 10 "$build/$program" "${args[@]}" >"$tmp/out" 2>"$tmp/err") || status=$?
  why=()
  [[ "$status" == "$expect" ]] || why+=("exit $status, not $expect")
  [[ "$(wc -l <"$tmp/err")" == 1 ]] && grep -qE "^($program|report): " "$tmp/err" || why+=("not one line on stderr")
  [[ ! -e "$tmp/refused-run" ]] || why+=("left {tmp}/refused-run behind")
  rm -rf "$tmp/refused-run"
  if LC_ALL=C grep -aqP "$acts_on_terminal" "$tmp/out" "$tmp/err"; then why+=("printed what a terminal acts on"); fi
  if (( ${#why[@]} )); then
    failed=$((failed + 1))
    printf 'FAIL %s: %s\n  stderr: %s\n' "$line" "$(IFS=';'; echo "${why[*]}")" "$(head -c 400 "$tmp/err" | cat -v)"
  fi
done <"$set_dir/cases"
[[ -z "$(ls -A "$tmp/elsewhere")" ]] || { echo "FAIL: files written through linked-out/gallery"; failed=$((failed + 1)); }
echo "hostile set: $((cases - failed)) of $cases cases held"
(( failed == 0 ))
