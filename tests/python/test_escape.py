"""escape: one rule per output format."""
import json

from heightmarch_tools import escape


def test_terminal_escapes_controls_and_keeps_text():
    assert escape.terminal("rock\x1b]0;PWN\x07.png") == "rock\\x1b]0;PWN\\x07.png"
    assert escape.terminal("a\x9bb") == "a\\xc2\\x9bb"  # an 8-bit CSI
    assert escape.terminal("x\u202ey") == "x\\xe2\\x80\\xaey"  # a right-to-left override
    assert escape.terminal("b\udcffad") == "b\\xffad"  # an undecodable byte kept by surrogateescape
    assert escape.terminal("héightmarch ✓") == "héightmarch ✓"


def test_html_escapes_markup():
    assert escape.html('<img src=x onerror="a">&') == "&lt;img src=x onerror=&quot;a&quot;&gt;&amp;"


def test_script_json_cannot_end_the_element_or_open_a_comment():
    data = {"label": "</script><!--<script>&\u2028"}
    text = escape.script_json(data)
    for bad in ("</", "<!--", "<", ">", "&", "\u2028"):
        assert bad not in text
    assert json.loads(text) == data


def test_markdown_leaves_no_link_html_heading_or_row_break():
    text = escape.markdown("[x](javascript:alert(1)) <b>|</b>\n### h #")
    assert "](" not in text.replace("\\](", "")
    assert "\n" not in text and "<b>" not in text and "|" not in text.replace("\\|", "")
    assert text == "\\[x\\](javascript:alert(1)) \\<b\\>\\|\\</b\\> \\#\\#\\# h \\#"


def test_markdown_target_is_one_destination():
    assert escape.markdown_target("gallery/a b (1).png") == "gallery/a%20b%20%281%29.png"


def test_csv_cell_neutralises_formulas_once():
    for cell in ("=HYPERLINK(\"x\")", "@SUM(A1)", "+cmd", "-2+3", "\tx", "\rx"):
        assert escape.csv_cell(cell) == "'" + cell
        assert escape.csv_cell(escape.csv_cell(cell)) == "'" + cell
    assert escape.csv_cell("bricks") == "bricks"


def test_terminal_line_keeps_head_and_tail_of_a_long_line_and_never_splits_an_escape():
    assert escape.terminal_line("short \x1b") == "short \\x1b"
    line = escape.terminal_line("--gl-device '" + "\x1b" * 4000 + "D" * 6000 + "': EGL lists software")
    assert len(line) <= escape.MAX_LINE + 40 and line.startswith("--gl-device '\\x1b")
    assert line.endswith("D': EGL lists software") and "characters cut]..." in line
    head = line.split("...[")[0]
    assert head.endswith("\\x1b") and "\x1b" not in line  # whole escapes only
    cut, tail = int(line.split("...[")[1].split(" ")[0]), line.split("]...")[1]
    assert cut == 4000 + 6000 - head.count("\\x1b") - tail.count("D")  # the count of what is cut is right
