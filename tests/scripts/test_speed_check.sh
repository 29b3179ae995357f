#!/usr/bin/env bash
# regress's detector (heightmarch_tools.speed_check.judge) on synthetic rounds shaped like this VM's
# (seeded, so the same every run): 1-thread CPU times with 1% noise per repetition and, in some
# rounds, a whole side in the slow mode (+35%, the core shared). Identical builds in 200 runs of 9
# benchmarks flag at most 5% of the runs (Benjamini-Hochberg at 0.05); a 5% slow-down of one
# benchmark is found in every one of 50 runs although a slow-mode round sits among its 12 rounds;
# a 0.3% slow-down, below the minimum effect, never is. No build needed.
# Usage: test_speed_check.sh [BUILD_DIR] (unused)
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"

PYTHONPATH="$root/scripts" /usr/bin/python3 - <<'PY'
import random, sys
from heightmarch_tools.speed_check import judge

NAMES = ["BM_Trace/technique:t%d/isa:avx2/threads:1" % i for i in range(9)]
rng = random.Random(22)


def side(cost, slow):
    return {"cpu_time": [cost * (1.35 if slow else 1.0) * rng.lognormvariate(0, 0.01) for _ in range(10)],
            "real_time": [1.0] * 10}


def rounds(slower=None, factor=1.0, slow_rounds=()):
    """12 rounds; in slow_rounds one side (alternately) ran wholly in the slow mode."""
    out = []
    for i in range(12):
        slow_old, slow_new = (i in slow_rounds and i % 2 == 0), (i in slow_rounds and i % 2 == 1)
        out.append({"load": 1.0,
                    "old": {n: side(1e-2, slow_old) for n in NAMES},
                    "new": {n: side(1e-2 * (factor if n == slower else 1.0), slow_new) for n in NAMES}})
    return out


def flagged(rs):
    return [v.pair[0] for v in judge(rs, [(n, n) for n in NAMES], 0.01, 0.05) if v.regressed]


def fail(what):
    print("FAIL: " + what)
    sys.exit(1)


false = sum(bool(flagged(rounds(slow_rounds=rng.sample(range(12), rng.randint(0, 2))))) for _ in range(200))
if false > 10:
    fail("identical builds flagged in %d of 200 runs of 9 benchmarks" % false)
print("ok: identical builds: %d of 200 runs of 9 benchmarks flag anything" % false)

found = [flagged(rounds(NAMES[3], 1.05, slow_rounds=[rng.randrange(12)])) for _ in range(50)]
if any(f != [NAMES[3]] for f in found):
    fail("a 5%% slow-down with a slow-mode round: flagged %s" % next(f for f in found if f != [NAMES[3]]))
print("ok: a 5% slow-down of one benchmark is found in 50 of 50 runs despite a slow-mode round")

small = [flagged(rounds(NAMES[3], 1.003)) for _ in range(20)]
if any(small):
    fail("a 0.3%% slow-down, below the minimum effect of 1%%, was flagged: %s" % small)
print("ok: a 0.3% slow-down (below the 1% minimum effect) is never flagged")
PY
