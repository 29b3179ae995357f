"""measurements: a run's files read and checked, every bad value one line naming its field."""
import json
import os
import subprocess
import sys

import pytest

from heightmarch_tools import measurements, report_page
from heightmarch_tools.errors import Unusable

SCRIPTS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts")


def run_data():
    view = {"kind": "default", "width": 64, "height": 64, "theta": None, "phi": None}
    row = {"id": 0, "kind": "trace", "purposes": ["matrix"], "technique": "pom", "layers": "32", "min_layers": 32,
           "max_layers": 32, "backend": "avx2", "threads": 2,
           "heightfield": {"label": "bricks", "source": "builtin:bricks", "width": 32, "height": 32}, "view": view,
           "rays": 4096, "samples": 40960, "samples_known": True, "samples_per_ray": 10.0,
           "errors": {"uv_error_mean": 0.5, "uv_error_p99": 1.5, "wrong_surface_rate": 0.1},
           "speed": {"repetitions": 2, "seconds": [1e-4, 1.1e-4], "rays_per_second": {"rounds": [4.1e7, 3.7e7]}},
           "images": {"render": "gallery/bricks-pom-32-render.png", "error": "gallery/bricks-pom-32-error.png"},
           "failure": None}
    return {"format": "heightmarch-measurements", "format_version": 2,
            "provenance": {"commit": "abc", "cpu": "Test CPU", "cores": 2, "date": "2026-01-01T00:00:00Z",
                           "best_isa": "avx2", "threads": 2},
            "plan": {"name": "test", "repetitions": 2}, "load": {"before": [0.1], "after": [0.2], "busy": False},
            "techniques": [{"name": "pom", "layered": True, "color": "#d62728", "marker": "s", "description": "d"}],
            "backends": ["scalar", "avx2", "glsl"], "rows": [row]}


def write_run(tmp_path, data):
    (tmp_path / "measurements.json").write_text(json.dumps(data) if not isinstance(data, str) else data)
    return str(tmp_path)


def test_a_valid_run_loads(tmp_path):
    run = measurements.load_run(write_run(tmp_path, run_data()))
    assert run.rows[0]["threads"] == 2 and run.heightfields == ["bricks"]
    assert [m["name"] for m in run.measures][:2] == ["uv_error_mean", "uv_error_rms"]  # a file without the list


def test_the_page_shows_the_measures_the_file_lists(tmp_path):
    data = run_data()
    data["measures"] = [{"name": "uv_error_p99", "label": "p99"}, {"name": "glint_error_mean", "label": "glint"}]
    data["rows"][0]["errors"]["glint_error_mean"] = 0.25
    run = measurements.load_run(write_run(tmp_path, data))
    assert report_page.page_rows(run)[0]["errors"] == {"uv_error_p99": 1.5, "glint_error_mean": 0.25}


def mutate(path, value):
    def change(data):
        target = data
        for key in path[:-1]:
            target = target[key]
        target[path[-1]] = value
        return data
    return change


ROW = ("rows", 0)
BAD = [
    (mutate(ROW + ("speed", "seconds", 0), 1e308), "rows[0]: speed: seconds[0]: is 1e+308, not in (0, 604800]"),
    (mutate(ROW + ("speed", "seconds"), []), "rows[0]: speed: seconds: has 0 values, fewer than 1"),
    (mutate(ROW + ("rays",), -1), "rows[0]: rays: is -1, not in 0.."),
    (mutate(ROW + ("id",), 1e20), "rows[0]: id: is 1e+20, not in 0..2147483647"),
    (mutate(ROW + ("errors", "uv_error_p99"), -5), "rows[0]: errors: uv_error_p99: is -5, not in [0,"),
    (mutate(ROW + ("threads",), "2"), "rows[0]: threads: is \"2\", not an integer"),
    (mutate(ROW + ("heightfield", "width"), 0.5), "rows[0]: heightfield: width: is 0.5, not an integer"),
    (mutate(ROW + ("images", "render"), "../../in/a/rock.png"), "rows[0]: images: render: is \"../../in/a/rock.png\", not a PNG"),
    (mutate(ROW + ("speed", "rays_per_second", "rounds"), [1.0]), "has 1 values for 2 repetitions' seconds"),
    (mutate(("techniques", 0, "color"), "red;background:url(x)"), "techniques[0]: color: is not a colour"),
    (mutate(("techniques", 0, "marker"), "$x$"), "techniques[0]: marker: is \"$x$\", none of"),
    (mutate(("rows",), [run_data()["rows"][0]] * 2), "rows[1]: id: is 0, the id of an earlier row"),
    (mutate(ROW + ("kind",), "\x1b[2J"), "rows[0]: kind: is \"\\u001b[2J\", none of"),
    (mutate(("measures",), [{"name": "<b>", "label": "x"}]), "measures[0]: name: is not a measure's name"),
    (mutate(ROW + ("layers",), "99999999999999999999"), "rows[0]: layers: is \"99999999999999999999\", not a layer"),
    (mutate(ROW + ("layers",), "8\x1b[2J"), "rows[0]: layers: is \"8\\u001b[2J\", not a layer count"),
    (mutate(ROW + ("layers",), 8), "rows[0]: layers: is 8, not a layer count"),
]


@pytest.mark.parametrize("change, why", BAD)
def test_a_bad_value_is_refused_naming_its_field(tmp_path, change, why):
    with pytest.raises(Unusable) as e:
        measurements.load_run(write_run(tmp_path, change(run_data())))
    assert why in str(e.value) and "\n" not in str(e.value) and "\x1b" not in str(e.value)


@pytest.mark.parametrize("text, why", [('{"format": NaN}', "NaN is not a number"),
                                       ('{"format": 1e400}', "beyond the range of a double")])
def test_json_that_is_not_strict_is_refused(tmp_path, text, why):
    with pytest.raises(Unusable) as e:
        measurements.load_run(write_run(tmp_path, text))
    assert why in str(e.value)


def test_what_is_not_a_file_is_refused_before_it_is_read(tmp_path):
    os.symlink("/dev/zero", tmp_path / "measurements.json")
    with pytest.raises(Unusable) as e:
        measurements.load_run(str(tmp_path))
    assert "character device" in str(e.value)


def test_the_report_says_it_in_one_line_and_exits_2(tmp_path):
    data = run_data()
    data["rows"][0]["heightfield"]["width"] = "wide"
    write_run(tmp_path, data)
    report = subprocess.run([sys.executable, os.path.join(SCRIPTS, "report"), str(tmp_path)], capture_output=True,
                            text=True)
    assert report.returncode == 2 and report.stderr.count("\n") == 1 and "Traceback" not in report.stderr
    assert "rows[0]: heightfield: width: is \"wide\", not an integer" in report.stderr


def test_recommendation_and_claims_are_checked(tmp_path):
    (tmp_path / "claims.json").write_text(json.dumps({"claims": [{"id": "C1", "claim": "x", "verdict": 3}]}))
    with pytest.raises(Unusable) as e:
        measurements.read_claims(str(tmp_path / "claims.json"))
    assert "claims[0]: verdict: is 3, not a string" in str(e.value)
    (tmp_path / "recommendation.json").write_text(json.dumps({"format_version": 1, "backends": [], "target": {
        "measure": "uv_error_p99", "uv_error_texels": -1, "wrong_surface_rate": 0.01, "frames": 1, "description": ""}}))
    with pytest.raises(Unusable) as e:
        measurements.read_optional(str(tmp_path / "recommendation.json"), "heightmarch-recommendation",
                                   measurements.validate_recommendation)
    assert "target: max_error: is -1" in str(e.value)  # format 1 read as the newest: its bound is max_error


def test_the_csv_header_is_neutralised_as_its_cells_are():
    row = dict(run_data()["rows"][0], **{"=HYPERLINK(\"http://x\")": "y"})
    header = measurements.measurements_csv([row]).splitlines()[0]
    assert "'=HYPERLINK" in header and ",=" not in header and not header.startswith("=")
