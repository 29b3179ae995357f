"""Benchmark results as compare, regress and bisect read them: Google Benchmark JSON (read by
readers.read_json) checked against its shape, and benchmark names in one canonical form.

Nothing here prints or exits: bad input raises Unusable with a one-line message.
"""
import math
import re

from .errors import Unusable
from .readers import is_number, quoted as shown, read_json

TIME_UNIT = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "ns": 1e-9}
# Name parts that say how Google Benchmark timed, not what ran: dropped when names are matched.
TIMING_SUFFIXES = ("real_time", "manual_time", "process_time")
SIZE_FIELDS = ("view", "depth_map")
# Fields of a benchmark entry that hold text; every other field but error_occurred is a number.
TEXT_FIELDS = ("name", "run_name", "run_type", "aggregate_name", "aggregate_unit", "time_unit", "error_message",
               "label", "big_o")


def check_entry(path, i, b):
    """One entry of "benchmarks" against Google Benchmark's shape (what compare.py also reads)."""
    where = "%s: benchmarks[%d]" % (path, i)
    if not isinstance(b, dict):
        raise Unusable("%s is %s, not an object" % (where, type(b).__name__))
    for key in TEXT_FIELDS:
        if key in b and not isinstance(b[key], str):
            raise Unusable("%s: %s is %s, not a string" % (where, key, shown(b[key])))
    if "name" not in b:
        raise Unusable("%s has no name" % where)
    where = "%s (%s)" % (where, shown(b["name"]))
    if b.get("run_type", "iteration") not in ("iteration", "aggregate"):
        raise Unusable("%s: run_type %s is neither iteration nor aggregate" % (where, shown(b["run_type"])))
    for key in ("repetitions", "repetition_index", "iterations", "threads"):
        if key in b and not (isinstance(b[key], int) and not isinstance(b[key], bool) and b[key] >= 0):
            raise Unusable("%s: %s is %s, not a count" % (where, key, shown(b[key])))
    if "error_occurred" in b and not isinstance(b["error_occurred"], bool):
        raise Unusable("%s: error_occurred is %s, not true or false" % (where, shown(b["error_occurred"])))
    if b.get("error_occurred"):
        return  # a failed benchmark carries no times
    if b.get("run_type", "iteration") == "iteration":
        for key in ("real_time", "cpu_time", "time_unit"):
            if key not in b:
                raise Unusable("%s has no %s" % (where, key))
    if "time_unit" in b and b["time_unit"] not in TIME_UNIT:
        raise Unusable("%s: time_unit %s is none of %s" % (where, shown(b["time_unit"]), ", ".join(TIME_UNIT)))
    for key in ("real_time", "cpu_time"):
        if key in b and not (is_number(b[key]) and math.isfinite(b[key]) and b[key] > 0):
            raise Unusable("%s: %s is %s, not a finite positive time" % (where, key, shown(b[key])))
    for key, value in b.items():
        # counters: numbers, or null (JSON's stand-in for NaN, as heightmarch writes a NaN measure)
        if key not in TEXT_FIELDS + ("error_occurred", "real_time", "cpu_time") and value is not None and not is_number(value):
            raise Unusable("%s: %s is %s, not a number" % (where, key, shown(value)))


def load_benchmarks(path):
    """A Google Benchmark JSON file, checked: an object with an optional "context" object and a
    "benchmarks" list whose iterations carry finite positive times in a known unit."""
    data = read_json(path, nonfinite=True)  # check_entry refuses a time that is not finite
    if not isinstance(data, dict) or not isinstance(data.get("benchmarks"), list):
        raise Unusable("%s: no \"benchmarks\" list: not Google Benchmark JSON output" % path)
    if not isinstance(data.get("context", {}), dict):
        raise Unusable("%s: \"context\" is %s, not an object" % (path, type(data["context"]).__name__))
    for i, b in enumerate(data["benchmarks"]):
        check_entry(path, i, b)
    return data


def context_value(data, key):
    """A context entry as text ("unknown" where missing); a single view's size reduced to WxH ("default
    1024x1024" and "1024x1024" are one), a view set kept whole ("around:1024x1024": another window)."""
    value = (data.get("context") or {}).get(key)
    value = "" if value is None or isinstance(value, (dict, list)) else str(value).strip()
    if key in ("heightmarch_view", "heightmarch_depth_map"):
        size = re.fullmatch(r"(?:default )?(\d+x\d+)", value)
        value = size.group(1) if size else value
    return value or "unknown"


def seconds(b, field="real_time"):
    return b[field] * TIME_UNIT[b["time_unit"]]


def clock(name):
    """The clock a benchmark is judged on: CPU time at 1 thread, where waiting for a core shared
    with other processes does not count (heightmarch-bench runs a 1-thread trace on its main
    thread, so revisions that measured the thread's CPU time measured the same); wall time
    otherwise: a slower parallel trace may spend no more CPU time, and a GLSL draw runs in
    llvmpipe's worker process, not in the one whose CPU time is counted. A suite's bench.json
    gives both as the wall time."""
    return "cpu_time" if "/threads:1/" in name + "/" and not name.startswith("BM_GLSL/") else "real_time"


# ---------------------------------------------------------------------------------------------
# Names

def fields(name):
    """{field: value} of a name's "field:value" parts."""
    return dict(p.split(":", 1) for p in name.split("/") if ":" in p)


def carries_sizes(data):
    return any("/view:" in b["name"] for b in data["benchmarks"])


def sizes_from_context(data, other):
    """This run's (field, size) pairs from its context when only the other run's names carry
    view:/depth_map: (heightmarch's names do since the sizes became part of them; older ones do not)."""
    if carries_sizes(data) or not carries_sizes(other):
        return []
    sizes = [(k, context_value(data, "heightmarch_" + k)) for k in SIZE_FIELDS]
    return [(k, v) for k, v in sizes if v != "unknown"]


def canonical(name, sizes=()):
    """The name without /min_time: and the timing suffix (/real_time of older runs, /manual_time of
    runs whose traces time themselves: both are one trace's wall time), with view:/depth_map: from
    sizes where the name lacks them."""
    parts = [p for p in name.split("/") if not p.startswith("min_time:") and p not in TIMING_SUFFIXES]
    at = max([i + 1 for i, p in enumerate(parts) if ":" in p] or [len(parts)])  # after the last field
    parts[at:at] = ["%s:%s" % (k, v) for k, v in sizes if k not in fields(name)]
    return "/".join(parts)


def iterations_by_name(data, sizes=()):
    """Iteration entries per canonical name, the raw name of each, and failed benchmarks
    {name: message}. Aggregates (_mean, _median, ...) are left out: they are made of the iterations."""
    runs, raw, errors = {}, {}, {}
    for b in data["benchmarks"]:
        if b.get("run_type", "iteration") != "iteration":
            continue
        name = canonical(b.get("run_name", b["name"]), sizes)
        if b.get("error_occurred"):
            errors[name] = b.get("error_message", "error")
        else:
            runs.setdefault(name, []).append(b)
            raw.setdefault(name, b.get("run_name", b["name"]))
    return runs, raw, errors


def matched_runs(old, new):
    """Both runs' iterations by canonical name, sizes taken from the context where one run's names
    lack them: (old_runs, new_runs, old_raw, new_raw, old_errors, new_errors, old_sizes, new_sizes)."""
    old_sizes, new_sizes = sizes_from_context(old, new), sizes_from_context(new, old)
    old_runs, old_raw, old_errors = iterations_by_name(old, old_sizes)
    new_runs, new_raw, new_errors = iterations_by_name(new, new_sizes)
    return old_runs, new_runs, old_raw, new_raw, old_errors, new_errors, old_sizes, new_sizes
