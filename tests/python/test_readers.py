"""readers: files checked before they are read, values checked as they are taken."""
import gzip
import os

import pytest

from heightmarch_tools import readers
from heightmarch_tools.errors import Unusable


def refused(call, *args, **kwargs):
    with pytest.raises(Unusable) as e:
        call(*args, **kwargs)
    assert "\n" not in str(e.value)
    return str(e.value)


def test_reads_a_regular_file(tmp_path):
    path = tmp_path / "a.json"
    path.write_text('{"a": [1, 2.5, null]}')
    assert readers.read_json(str(path)) == {"a": [1, 2.5, None]}


def test_reads_a_gzip_file_and_holds_what_it_unpacks_to_the_budget(tmp_path, monkeypatch):
    path = tmp_path / "measurements.json.gz"
    path.write_bytes(gzip.compress(b'{"a": [1, 2.5, null]}'))
    assert readers.read_json(str(path)) == {"a": [1, 2.5, None]}
    # A run's file found compressed or not, by its name.
    assert readers.run_file(str(tmp_path), "measurements.json") == str(path)
    (tmp_path / "measurements.json").write_text("{}")
    assert readers.run_file(str(tmp_path), "measurements.json") == str(tmp_path / "measurements.json")
    # 3 MB of zeros packs to a few KB: refused for what it unpacks to, not its size.
    bomb = tmp_path / "bomb.json.gz"
    bomb.write_bytes(gzip.compress(b"[" + b"0," * 1500000 + b"0]"))
    monkeypatch.setenv("HEIGHTMARCH_MEMORY_LIMIT", str(readers.resident_bytes() + (4 << 20)))  # 4 MiB left
    assert "unpacks to more than" in refused(readers.read_json, str(bomb))
    monkeypatch.delenv("HEIGHTMARCH_MEMORY_LIMIT")
    cut = tmp_path / "cut.json.gz"
    cut.write_bytes(gzip.compress(b'{"a": 1}' * 100)[:30])
    assert "not a whole gzip file" in refused(readers.read_json, str(cut))


def test_refuses_what_is_not_a_regular_file(tmp_path):
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    assert "is a FIFO, not a regular file" in refused(readers.read_json, str(fifo))  # and does not block
    assert "is a character device" in refused(readers.read_json, "/dev/zero")
    assert "is a directory" in refused(readers.read_json, str(tmp_path))
    assert "no such file" in refused(readers.read_json, str(tmp_path / "none"))
    link = tmp_path / "zero"
    os.symlink("/dev/zero", link)
    assert "character device" in refused(readers.read_json, str(link))


def test_refuses_a_file_beyond_the_memory_budget(tmp_path, monkeypatch):
    path = tmp_path / "big.json"
    path.write_text("[" + "0," * 200000 + "0]")
    monkeypatch.setenv("HEIGHTMARCH_MEMORY_LIMIT", "1M")
    assert "left of the memory budget" in refused(readers.read_json, str(path))
    monkeypatch.setenv("HEIGHTMARCH_MEMORY_LIMIT", "10X")
    assert "not a size" in refused(readers.read_json, str(path))


def test_memory_limit_syntax():
    assert readers.parse_memory_limit("512M") == 512 << 20
    assert readers.parse_memory_limit("1.5GiB") == 3 << 29
    assert readers.parse_memory_limit("100") == 100
    for bad in ("0", "-1", "1e30", "inf", "abc", "10X"):
        refused(readers.parse_memory_limit, bad)


def test_json_is_strict(tmp_path):
    for text, why in (("[NaN]", "NaN"), ("[Infinity]", "Infinity"), ("[1e400]", "beyond the range"),
                      ("[" * 100000 + "]" * 100000, "nested too deeply"), ("{", "invalid JSON"),
                      (b"\xff\xfe", "not UTF-8")):
        path = tmp_path / "x.json"
        path.write_bytes(text if isinstance(text, bytes) else text.encode())
        assert why in refused(readers.read_json, str(path))
    path.write_text("[NaN]")
    assert readers.read_json(str(path), nonfinite=True)[0] != readers.read_json(str(path), nonfinite=True)[0]


def test_csv_rows_have_their_line_numbers(tmp_path):
    path = tmp_path / "h.csv"
    path.write_text('a,b\n1,2\n"x\ny",4\n5\n')
    assert readers.read_csv(str(path), ["a", "b"]) == [(2, ["1", "2"]), (4, ["x\ny", "4"]), (5, ["5"])]
    path.write_text("a,c\n1,2\n")
    assert "line 1: the columns are not a,b" in refused(readers.read_csv, str(path), ["a", "b"])
    assert readers.read_csv(str(tmp_path / "none.csv"), ["a"]) == []
    path.write_text("a,b\n1,2\n3,\x004\n")
    assert "line 3: a NUL byte" in refused(readers.read_csv, str(path), ["a", "b"])


def test_values_are_checked_where_they_are():
    where = readers.Where("m.json")["rows"][3]
    assert where["threads"].integer(2.0, 1, 4096) == 2
    assert "m.json: rows[3]: threads: is 1e+20, not in 1..4096" == refused(where["threads"].integer, 1e20, 1, 4096)
    assert "not an integer" in refused(where["id"].integer, 1.5)
    assert "not an integer" in refused(where["id"].integer, True)
    assert "not a finite number" in refused(where["seconds"].number, "1")
    assert "not in (0, inf]" in refused(where["seconds"].number, 0, low_open=True)
    assert "not in [0, inf]" in refused(where["uv"].number, -5)
    assert where["uv"].number(None, none=True) is None
    assert where["x"].numbers([1, 2], least=2) == [1, 2]
    assert "fewer than 1" in refused(where["x"].numbers, [], least=1)
    assert "not a number" in refused(where["x"].decimal, "fast")
    assert where["x"].decimal("", empty=True) is None
    assert "\x1b" not in refused(where["kind"].one_of, "\x1b[2J", ("trace",))
