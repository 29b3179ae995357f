#!/usr/bin/env bash
# scripts/compare passes identical runs and flags a benchmark made 30% slower (with repetitions,
# so the U-test applies), naming it.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
write_run() {  # FILE SLOWDOWN_OF_POM
  /usr/bin/python3 - "$1" "$2" <<'PY'
import json, sys
path, slow = sys.argv[1], float(sys.argv[2])
benchmarks = []
for name, base in [("BM_Trace/heightfield:bricks/technique:pom/layers:32/isa:avx2/threads:1", 40.0),
                   ("BM_Trace/heightfield:bricks/technique:steep/layers:32/isa:avx2/threads:1", 30.0)]:
    for rep in range(9):
        t = base * (1.0 + 0.003 * ((rep * 7) % 5)) * (slow if "pom" in name else 1.0)
        benchmarks.append({"name": name, "run_name": name, "run_type": "iteration", "repetitions": 9,
                           "repetition_index": rep, "threads": 1, "iterations": 10, "real_time": t,
                           "cpu_time": t, "time_unit": "ms", "rays_per_second": 1e6 / t})
json.dump({"context": {"date": "x", "num_cpus": 2}, "benchmarks": benchmarks}, open(path, "w"))
PY
}
write_run "$tmp/old.json" 1.0
write_run "$tmp/same.json" 1.0
write_run "$tmp/slow.json" 1.3
"$root/scripts/compare" "$tmp/old.json" "$tmp/same.json" > "$tmp/same.out" || { cat "$tmp/same.out"; echo "FAIL: identical runs flagged"; exit 1; }
echo "ok: identical runs pass"
if "$root/scripts/compare" "$tmp/old.json" "$tmp/slow.json" > "$tmp/slow.out"; then
  cat "$tmp/slow.out"; echo "FAIL: a 30% slow-down passed"; exit 1
fi
grep -q "REGRESSION" "$tmp/slow.out" && grep -q "technique:pom" "$tmp/slow.out" || { cat "$tmp/slow.out"; echo "FAIL: regression not named"; exit 1; }
if grep "technique:steep" "$tmp/slow.out" | grep -q REGRESSION; then echo "FAIL: unchanged benchmark flagged"; exit 1; fi
echo "ok: the 30% slower benchmark is flagged, the unchanged one is not"
