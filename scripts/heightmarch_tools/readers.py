"""Every file a tool of this package reads, read one way: checked before it is read, then its
values checked as they are taken.

- The file: opened without blocking and without following a link planted at the end of a path
  we do not own only where asked; it must be a regular file (a FIFO, a device such as /dev/zero
  or a directory is refused before a byte is read) and small enough that it and what it becomes
  once parsed (PARSE_FACTOR times its size) fit in the memory budget: HEIGHTMARCH_MEMORY_LIMIT
  (the tool's own syntax: 512M, 1.5G) or half the RAM, as heightmarch's.
- JSON: strict (NaN, Infinity and numbers beyond a double, such as 1e400, are refused), nested
  at most as deep as Python parses.
- CSV: a header of the columns asked for, then rows with their line numbers.
- Values: `Where` names the place of a value in its file ("measurements.json: row 17: threads")
  and checks it: a string, a finite number within a range, an integer count or id.

Nothing here prints or exits: what is wrong raises errors.Unusable with one line.
"""
import csv
import io
import json
import math
import os
import re
import stat
import zlib

from .errors import Unusable
from .escape import terminal

# A parsed JSON file holds about 3 times its size in Python objects (measured on a full run's
# measurements.json and bench.json: 3.2x and 1.9x), beside the text itself: 8 leaves room.
PARSE_FACTOR = 8
MAX_SHOWN = 120  # an error line quotes at most this much of a value
_SIZE = re.compile(r"(\d{1,39})(\.\d{0,39})?(?:([KMGT])(I?B)?|B)?", re.IGNORECASE)


# ---------------------------------------------------------------------------------------------
# The memory budget

def parse_memory_limit(text, name="HEIGHTMARCH_MEMORY_LIMIT"):
    """Bytes of a size as heightmarch's --memory-limit takes it: digits, an optional fraction, an
    optional suffix K, M, G or T (powers of 1024, optionally followed by B or iB)."""
    m = _SIZE.fullmatch(text.strip())
    if not m:
        raise Unusable("%s=%r: not a size (bytes, or a number with a suffix K, M, G or T: 512M, 1.5G)" % (name, text))
    value = float(m.group(1) + (m.group(2) or ""))
    scale = 1024 ** ("KMGT".index(m.group(3).upper()) + 1) if m.group(3) else 1
    size = math.floor(value * scale)
    if not 1 <= size <= 2 ** 62:
        raise Unusable("%s=%r: a budget of at least 1 byte and at most 2^62" % (name, text))
    return size


def memory_budget():
    """(bytes, where they come from): HEIGHTMARCH_MEMORY_LIMIT, else half the physical memory."""
    limit = os.environ.get("HEIGHTMARCH_MEMORY_LIMIT")
    if limit:
        return parse_memory_limit(limit), "HEIGHTMARCH_MEMORY_LIMIT"
    try:
        return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE") // 2, "half the RAM"
    except (ValueError, OSError):
        return 4 << 30, "a default of 4 GiB"


def resident_bytes():
    try:
        with open("/proc/self/statm") as f:
            return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError):
        return 0


def size_text(n):
    for unit in ("bytes", "KiB", "MiB", "GiB", "TiB"):
        if n < 1024 or unit == "TiB":
            return "%d bytes" % n if unit == "bytes" else "%.1f %s" % (n, unit)
        n /= 1024.0


# ---------------------------------------------------------------------------------------------
# Files

GZIP_MAGIC = b"\x1f\x8b"


def run_file(run_dir, name):
    """A run's file NAME, or NAME.gz where the run keeps it compressed (a committed run's large
    files); NAME where neither is there, for the reader's one-line refusal."""
    path = os.path.join(run_dir, name)
    return path + ".gz" if not os.path.exists(path) and os.path.exists(path + ".gz") else path


def gunzip(data, limit, shown):
    """A gzip file's contents, refused once they pass limit bytes (a small file may unpack to any
    size: the budget holds for what it unpacks to, not for its size)."""
    inflater = zlib.decompressobj(wbits=31)
    try:
        out = inflater.decompress(data, limit + 1)
    except zlib.error as e:
        raise Unusable("%s: not a whole gzip file (%s)" % (shown, e))
    if len(out) > limit:
        raise Unusable("%s: unpacks to more than the %s the memory budget leaves" % (shown, size_text(limit)))
    if not inflater.eof:
        raise Unusable("%s: not a whole gzip file (it ends early)" % shown)
    return out


def read_bytes(path, factor=PARSE_FACTOR):
    """The whole of a regular file whose size, times factor, fits in what the memory budget leaves;
    a gzip file (by its first two bytes) unpacked, within the budget too."""
    shown = terminal(path)
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC)  # a FIFO opens without a writer
    except FileNotFoundError:
        raise Unusable("%s: no such file" % shown)
    except OSError as e:
        raise Unusable("%s: cannot open: %s" % (shown, e.strerror))
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise Unusable("%s: is %s, not a regular file" % (shown, file_kind(st.st_mode)))
        budget, source = memory_budget()
        left = max(budget - resident_bytes(), 0)
        if st.st_size * factor > left:
            raise Unusable("%s: %s would need about %s to read, more than the %s left of the memory budget (%s, %s)" % (
                shown, size_text(st.st_size), size_text(st.st_size * factor), size_text(left), size_text(budget), source))
        chunks, remaining = [], st.st_size
        while remaining > 0:  # a file that grew is read to its size when opened, one that shrank to its end
            chunk = os.read(fd, min(remaining, 1 << 24))
            if not chunk:
                break
            chunks.append(chunk)
            remaining -= len(chunk)
        data = b"".join(chunks)
        return gunzip(data, int(left / factor), shown) if data[:2] == GZIP_MAGIC else data
    except OSError as e:
        raise Unusable("%s: cannot read: %s" % (shown, e.strerror))
    finally:
        os.close(fd)


def file_kind(mode):
    for test, kind in ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO"), (stat.S_ISCHR, "a character device"),
                       (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return kind
    return "not a regular file"


def read_text(path):
    try:
        return read_bytes(path).decode("utf-8")
    except UnicodeDecodeError as e:
        raise Unusable("%s: not UTF-8 text (byte %d)" % (terminal(path), e.start))


def _refuse_constant(name):
    raise ValueError("%s is not a number JSON allows" % name)


def _finite_float(text):
    value = float(text)
    if not math.isfinite(value):
        raise ValueError("%s is beyond the range of a double" % text[:MAX_SHOWN])
    return value


def parse_json(text, what, nonfinite=False):
    """Strict JSON: no NaN or Infinity, no number beyond a double; with nonfinite, those are
    read as the floats they name, for a reader that checks each field itself (Google Benchmark
    writes a NaN counter as NaN)."""
    try:
        if nonfinite:
            return json.loads(text)
        return json.loads(text, parse_constant=_refuse_constant, parse_float=_finite_float)
    except RecursionError:
        raise Unusable("%s: nested too deeply" % what)
    except json.JSONDecodeError as e:
        raise Unusable("%s: invalid JSON: %s" % (what, e))
    except ValueError as e:
        raise Unusable("%s: invalid JSON: %s" % (what, e))


def read_json(path, nonfinite=False):
    """The parsed file (parse_json), or Unusable naming the file and what is wrong with it."""
    return parse_json(read_text(path), terminal(path), nonfinite)


def read_csv(path, columns):
    """[(line number, cells)] of a CSV file whose header is `columns` ([] where the file does not
    exist yet); the cells of each row are for the caller to check (history.Table.check)."""
    if not os.path.lexists(path):
        return []
    shown = terminal(path)
    text = read_text(path)
    if "\0" in text:  # no file the tool writes holds one (Python's csv module reads it as a character)
        raise Unusable("%s: line %d: a NUL byte" % (shown, text.count("\n", 0, text.index("\0")) + 1))
    reader = csv.reader(io.StringIO(text, newline=""))
    try:
        header = next(reader, None)
        if header is None:
            return []
        if header != list(columns):
            raise Unusable("%s: line 1: the columns are not %s" % (shown, ",".join(columns)))
        return [(reader.line_num, cells) for cells in reader]
    except csv.Error as e:
        raise Unusable("%s: line %d: %s" % (shown, reader.line_num, e))


def quoted(value):
    """A value as an error line quotes it: JSON, one line, printable, short."""
    text = terminal(json.dumps(value))
    return text if len(text) <= MAX_SHOWN else text[:MAX_SHOWN] + "..."


# ---------------------------------------------------------------------------------------------
# Values

def is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool)


class Where:
    """The place of values in a file, for their checks' one-line errors: Where("m.json")["rows"][3]."""

    def __init__(self, place):
        self.place = place

    def __getitem__(self, key):
        return Where("%s[%d]" % (self.place, key) if isinstance(key, int) else "%s: %s" % (self.place, key))

    def __str__(self):
        return self.place

    def refuse(self, why):
        raise Unusable("%s: %s" % (self.place, why))

    def check(self, condition, why):
        if not condition:
            self.refuse(why)

    def object(self, value, keys=()):
        """A JSON object with at least these keys."""
        if not isinstance(value, dict):
            self.refuse("is %s, not an object" % quoted(value))
        missing = [k for k in keys if k not in value]
        if missing:
            self.refuse("has no %s" % ", ".join(missing))
        return value

    def list(self, value):
        if not isinstance(value, list):
            self.refuse("is %s, not a list" % quoted(value))
        return value

    def text(self, value, none=False):
        if value is None and none:
            return None
        if not isinstance(value, str):
            self.refuse("is %s, not a string" % quoted(value))
        return value

    def number(self, value, low=0.0, high=math.inf, none=False, low_open=False):
        """A finite number in [low, high] ((low, high] with low_open); None where none allows it."""
        if value is None and none:
            return None
        if not is_number(value) or not math.isfinite(value):
            self.refuse("is %s, not a finite number" % quoted(value))
        if value < low or (low_open and value == low) or value > high:
            self.refuse("is %s, not in %s%g, %g]" % (quoted(value), "(" if low_open else "[", low, high))
        return value

    def integer(self, value, low=0, high=2 ** 53, none=False):
        """An integer in [low, high] (a JSON number with no fraction: 3 or 3.0)."""
        if value is None and none:
            return None
        if not is_number(value) or not math.isfinite(value) or value != int(value):
            self.refuse("is %s, not an integer" % quoted(value))
        if not low <= value <= high:
            self.refuse("is %s, not in %d..%d" % (quoted(value), low, high))
        return int(value)

    def boolean(self, value):
        if not isinstance(value, bool):
            self.refuse("is %s, not true or false" % quoted(value))
        return value

    def one_of(self, value, allowed):
        if value not in allowed:
            self.refuse("is %s, none of %s" % (quoted(value), ", ".join(map(str, allowed))))
        return value

    def numbers(self, value, low=0.0, high=math.inf, low_open=False, least=0):
        """A list of at least `least` finite numbers in range."""
        values = self.list(value)
        self.check(len(values) >= least, "has %d values, fewer than %d" % (len(values), least))
        return [self[i].number(v, low, high, low_open=low_open) for i, v in enumerate(values)]

    def decimal(self, text, low=0.0, high=math.inf, empty=False):
        """A number written as text (a CSV cell): finite, in range; None for "" where empty allows it."""
        if text == "" and empty:
            return None
        try:
            value = float(text)
        except ValueError:
            self.refuse("is %s, not a number" % quoted(text))
        return self.number(value, low, high)
