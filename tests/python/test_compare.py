"""compare's speed rule: the machine's shift from the controls, the whole run's verdict, small runs."""
import argparse
import random

import pytest

from heightmarch_tools import compare
from heightmarch_tools.errors import Unusable

ARGS = argparse.Namespace(threshold=0.05, small_threshold=compare.SMALL_THRESHOLD, fdr=0.05)


def names(count):
    return ["BM_Trace/heightfield:h%d/technique:t%d/layers:32/isa:avx2/threads:1" % (i, i % 4) for i in range(count)]


CONTROLS = ["BM_Calibration/heightfield:h0/isa:calibration/threads:1", "BM_Calibration/heightfield:h0/isa:calibration/threads:2",
            "BM_GLSL/heightfield:h0/technique:pom/layers:32/isa:glsl/threads:1"]


def runs(benchmarks, factor=lambda name: 1.0, reps=5, seed=1):
    rng = random.Random(seed)
    out = {}
    for n in benchmarks:
        times = [10.0 * factor(n) * rng.uniform(0.99, 1.01) for _ in range(reps)]
        out[n] = [{"real_time": t, "cpu_time": t, "time_unit": "ms"} for t in times]
    return out


def judge(old, new, changed=None):
    return compare.judge_speed(old, new, [n for n in old if n in new], changed or {}, ARGS)


def test_controls():
    assert compare.control_kind("BM_Calibration/heightfield:h0/isa:calibration/threads:1") == "calibration"
    assert compare.control_kind("BM_GLSL/heightfield:h0/technique:pom/layers:32/isa:glsl/threads:1") == "glsl"
    # a renderer other than llvmpipe (a GPU) is as much the code's as the machine's
    assert compare.control_kind("BM_GLSL/heightfield:h0/technique:pom/renderer:nvidia/isa:glsl/threads:1") is None
    assert compare.control_kind("BM_Trace/heightfield:h0/technique:pom/layers:32/isa:avx2/threads:1") is None


def test_families_keep_series_keys_apart():
    assert compare.family("BM_Trace/heightfield:h0/technique:pom/layers:32/isa:avx2/threads:1/view:64x64") == \
        "BM_Trace/technique:pom"
    assert compare.family("BM_GLSL/heightfield:h0/technique:pom/renderer:llvmpipe/layers:32/isa:glsl/threads:1") == \
        "BM_GLSL/technique:pom/renderer:llvmpipe"


def test_a_uniform_slow_down_fails_whatever_the_controls_say():
    all_names = names(24) + CONTROLS
    machine = judge(runs(all_names), runs(all_names, lambda n: 1.2, seed=2))["run"]
    assert machine["slower"] and machine["cause"] == "machine"
    code = judge(runs(all_names), runs(all_names, lambda n: 1.0 if n in CONTROLS else 1.2, seed=2))
    assert code["run"]["cause"] == "code" and all(v[3] for n, v in code["benchmarks"].items() if n not in CONTROLS)
    without = judge(runs(names(24)), runs(names(24), lambda n: 1.2, seed=2))["run"]
    assert without["slower"] and without["cause"] == "unknown" and without["control_shift"] is None


def test_a_glsl_row_that_changed_behaviour_is_no_control():
    all_names = names(24) + CONTROLS
    j = judge(runs(all_names), runs(all_names, seed=2), changed={CONTROLS[2]: ["uv_error_mean 1 -> 2"]})
    assert j["benchmarks"][CONTROLS[2]][4] == "code"
    assert j["run"]["control_shift"] is None  # two controls left, three needed


def test_the_machine_is_taken_out():
    all_names = names(24) + CONTROLS
    j = judge(runs(all_names), runs(all_names, lambda n: 1.03, seed=2))
    assert not j["run"]["slower"] and not any(v[3] for v in j["benchmarks"].values())
    assert j["run"]["control_shift"] == pytest.approx(0.03, abs=0.01)


def test_small_runs():
    few = names(10)
    moved = judge(runs(few), runs(few, lambda n: 1.25, seed=2))  # below the small-run minimum effect
    assert moved["run"]["small"] and not any(v[3] for v in moved["benchmarks"].values())
    slower = judge(runs(few), runs(few, lambda n: 1.5 if n == few[0] else 1.0, seed=2))
    assert [n for n, v in slower["benchmarks"].items() if v[3]] == [few[0]]
    with pytest.raises(Unusable, match="none with repetitions"):
        judge(runs(few, reps=1), runs(few, reps=1, seed=2))
