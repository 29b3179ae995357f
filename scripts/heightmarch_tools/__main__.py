"""python3 -m heightmarch_tools COMMAND ARGS: the commands of the package, as the installed tool
runs them (heightmarch report, heightmarch suite's report stage).

    report RUN_DIR [--history HISTORY.csv]   the run's report (heightmarch_tools.report)
    repair-history HISTORY.csv [--dry-run]   the history without the rows it cannot read, each named
"""
import sys

from . import cli

COMMANDS = {"report": "report", "repair-history": "history:repair"}

if len(sys.argv) < 2 or sys.argv[1] not in COMMANDS:
    print("usage: python3 -m heightmarch_tools {%s} ARGS" % ",".join(COMMANDS), file=sys.stderr)
    sys.exit(2)
sys.exit(cli.run(sys.argv[1], COMMANDS[sys.argv[1]], sys.argv[2:]))
