"""benchmark_results: Google Benchmark JSON's shape and names, as compare and regress read them."""
import json

import pytest

from heightmarch_tools import benchmark_results as br
from heightmarch_tools.errors import Unusable

NAME = "BM_Trace/heightfield:bricks/technique:pom/layers:32/isa:avx2/threads:1/view:64x64/depth_map:32x32/manual_time"


def entry(**changes):
    return dict({"name": NAME, "run_type": "iteration", "real_time": 2.0, "cpu_time": 1.5, "time_unit": "ms",
                 "uv_error_mean": 0.25, "shadow_error_mean": None}, **changes)


def write(tmp_path, data):
    path = tmp_path / "bench.json"
    path.write_text(json.dumps(data))
    return str(path)


def test_a_well_formed_file_loads(tmp_path):
    data = br.load_benchmarks(write(tmp_path, {"context": {}, "benchmarks": [entry()]}))
    assert br.seconds(data["benchmarks"][0]) == 0.002


@pytest.mark.parametrize("bad, why", [
    ({"real_time": -1.0}, "not a finite positive time"), ({"time_unit": "h"}, "time_unit"),
    ({"name": 3}, "not a string"), ({"iterations": -2}, "not a count"), ({"uv_error_mean": "x"}, "not a number"),
    ({"run_type": "other"}, "neither iteration nor aggregate")])
def test_a_malformed_entry_is_one_line(tmp_path, bad, why):
    with pytest.raises(Unusable) as e:
        br.load_benchmarks(write(tmp_path, {"benchmarks": [entry(**bad)]}))
    assert why in str(e.value) and "benchmarks[0]" in str(e.value)


def test_not_benchmark_json(tmp_path):
    with pytest.raises(Unusable):
        br.load_benchmarks(write(tmp_path, {"rows": []}))


def test_canonical_names_match_across_formats():
    old = "BM_Trace/heightfield:bricks/technique:pom/layers:32/isa:avx2/threads:1/min_time:0.100/real_time"
    assert br.canonical(old, [("view", "64x64"), ("depth_map", "32x32")]) == NAME[:-len("/manual_time")]
    assert br.canonical(NAME) == NAME[:-len("/manual_time")]
    assert br.fields(NAME)["isa"] == "avx2"


def test_sizes_come_from_the_context_only_where_the_other_run_names_them():
    named = {"benchmarks": [entry()]}
    bare = {"context": {"heightmarch_view": "default 64x64", "heightmarch_depth_map": "32x32"},
            "benchmarks": [entry(name="BM_Trace/isa:avx2/real_time")]}
    assert br.sizes_from_context(bare, named) == [("view", "64x64"), ("depth_map", "32x32")]
    assert br.sizes_from_context(named, bare) == []
