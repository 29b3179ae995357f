#!/usr/bin/env bash
# The kept hostile set (hostile_inputs.py, its cases in hostile_cases.py): issue 32's six classes
# run from outside against the built tool, its report, the GLSL worker and the scripts, each case
# with its one expected outcome (exit status, one line, no traceback, no hang, nothing written
# outside its run, nothing left running). About 40 s of CPU and 90 s of wall time.
# Usage: test_hostile_inputs.sh BUILD_DIR
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
exec /usr/bin/python3 "$here/hostile_inputs.py" "${1:?usage: test_hostile_inputs.sh BUILD_DIR}"
