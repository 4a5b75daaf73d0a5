#!/usr/bin/env bash
# Lays out every C++ file of src/, include/, drivers/ and tests/ as .clang-format says, in
# place (clang-format 14, Debian 12's; tests/cli/format.sh checks the result in CI).
# Usage: bash jobs/tools/format.sh   (from anywhere; GRANPACK_CLANG_FORMAT names another binary)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
clang_format=${GRANPACK_CLANG_FORMAT:-clang-format}
find src include drivers tests -type f \( -name '*.cpp' -o -name '*.h' \) -print0 |
  xargs -0 "$clang_format" -i
