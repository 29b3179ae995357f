# shellcheck shell=bash
# Sourced by the script tests (tests/scripts/test_*.sh) right after `set -euo pipefail`: the
# repository's root, a scratch directory removed on exit, and fail() (a test may define its own).
# shellcheck disable=SC2034  # root is for the tests that source this
root="$(cd "$(dirname "${BASH_SOURCE[1]}")/../.." && pwd)"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
