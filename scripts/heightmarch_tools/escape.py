"""One escaping rule per output format, applied where a string from a file (a map's name, a label, a
provenance field, a message) enters that format, never where it is made:

- terminal: control characters, C1 controls and bidirectional overrides as \\xNN (the rule of the
  C++ printable(), src/util/error.cpp), for every line a tool prints; terminal_line for an error
  line, cut in its middle beyond MAX_LINE characters (the C++ error_line());
- html: text through html.escape (the page's script sets textContent, never innerHTML with data);
  data embedded in a <script> element as JSON with <, > and & as \\u escapes, so no name ends
  the element (</script>) or opens a comment (<!--);
- markdown: the characters that make markup escaped with a backslash and line breaks made spaces,
  so a name is text in a cell, a heading or a paragraph (no link, no image, no HTML, no new row);
  link targets percent-encoded;
- csv: a text cell that begins with = + - @, a tab or a carriage return prefixed with ' (OWASP's
  rule against formula injection in spreadsheets).
"""
import html as html_module
import json
import urllib.parse

# The C1 controls (an 8-bit CSI is U+009B) and the bidirectional embeddings, overrides and
# isolates, which reorder what follows them on the line.
_ACTS_ON_TERMINAL = set(range(0x80, 0xA0)) | set(range(0x202A, 0x202F)) | set(range(0x2066, 0x206A))
_MARKDOWN_SPECIAL = set("\\`*_[]<>#|~&$")
_FORMULA_START = ("=", "+", "-", "@", "\t", "\r")
MAX_LINE = 1000  # characters of an error line (heightmarch's kMaxErrorLine)


def terminal(text):
    """text safe to print on a terminal: control characters as \\xNN (the bytes of their UTF-8
    form), bytes that were not UTF-8 (decoded with surrogateescape) as \\xNN of the byte."""
    return "".join(_terminal_character(c) for c in str(text))


def _terminal_character(c):
    code = ord(c)
    if code < 0x20 or code == 0x7F:
        return "\\x%02x" % code
    if 0xDC80 <= code <= 0xDCFF:  # an undecodable byte, as surrogateescape keeps it
        return "\\x%02x" % (code - 0xDC00)
    if code in _ACTS_ON_TERMINAL or 0xD800 <= code <= 0xDFFF:
        return "".join("\\x%02x" % b for b in c.encode("utf-8", "surrogatepass"))
    return c


def terminal_line(text, limit=MAX_LINE):
    """terminal(text) of at most about limit characters: a longer one keeps its head and its tail
    (where an error line says what is wrong) around a note of what was cut, never splitting an
    escape. An error line that echoes a user's string (a 10 KB device name) stays a line."""
    pieces = [_terminal_character(c) for c in str(text)]
    if sum(map(len, pieces)) <= limit:
        return "".join(pieces)
    head, tail, used = [], [], 0
    for piece in pieces:  # three fifths of the line for the head
        if used + len(piece) > limit * 3 // 5:
            break
        head.append(piece)
        used += len(piece)
    used = 0
    for piece in reversed(pieces[len(head):]):  # a third for the tail
        if used + len(piece) > limit // 3:
            break
        tail.append(piece)
        used += len(piece)
    cut = len(pieces) - len(head) - len(tail)
    return "%s...[%d characters cut]...%s" % ("".join(head), cut, "".join(reversed(tail)))


def html(text):
    """Text as HTML text or an attribute's value."""
    return html_module.escape(str(text), quote=True)


def script_json(data):
    """data as JSON to embed in a <script type="application/json"> element: strict JSON (no NaN),
    with <, > and & (and the JavaScript line separators) as \\u escapes that JSON.parse reads back."""
    text = json.dumps(data, separators=(",", ":"), allow_nan=False)
    for c in "<>&\u2028\u2029":
        text = text.replace(c, "\\u%04x" % ord(c))
    return text


def markdown(text):
    """Text as Markdown text, in a table cell, a heading or a paragraph: printable on a terminal,
    markup characters escaped, line breaks and tabs as spaces."""
    out = []
    for c in terminal(str(text).replace("\r\n", " ").replace("\n", " ").replace("\r", " ").replace("\t", " ")):
        out.append("\\" + c if c in _MARKDOWN_SPECIAL else c)
    return "".join(out)


def markdown_target(path):
    """A relative path as a Markdown link or image target: percent-encoded, so no space,
    parenthesis or angle bracket ends it."""
    return urllib.parse.quote(str(path), safe="/#-._~")


def csv_cell(text):
    """A CSV cell's text: one that begins with = + - @, a tab or a carriage return is prefixed with
    ' so a spreadsheet shows it instead of evaluating it. Idempotent: a prefixed cell stays as it is."""
    text = str(text)
    return "'" + text if text.startswith(_FORMULA_START) else text
