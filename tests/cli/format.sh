#!/usr/bin/env bash
# Every C++ file of src/, include/, drivers/ and tests/ is formatted as the repository's own
# .clang-format says (issue 30): `clang-format --dry-run --Werror` on each, the files that
# differ named with the first lines of their diff. To reformat after an edit:
#   bash jobs/tools/format.sh
# The tree is formatted with Debian 12's clang-format 14 (jobs/setup.sh installs it). Another
# major version lays some lines out differently, so with one the check is skipped (exit 77,
# "Skipped" in ctest) rather than failing on a tree that is right for version 14.
# A text check, no build needed.
# ctest: PROCESSORS 1
set -u
: "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch

clang_format=${GRANPACK_CLANG_FORMAT:-clang-format}
if ! command -v "$clang_format" > /dev/null; then
  check "clang-format is installed (bash jobs/setup.sh build installs it)" false
  checks_done format
  exit 1
fi
version=$("$clang_format" --version)
major=$(sed -E 's/.*version ([0-9]+)\..*/\1/' <<< "$version")
if [ "$major" != 14 ]; then
  echo "format: skipped, the tree is laid out by clang-format 14; this is: $version"
  exit 77
fi

cd "$GRANPACK_SOURCE_DIR"
mapfile -t files < <(find src include drivers tests -type f \( -name '*.cpp' -o -name '*.h' \) | sort)
check "C++ files found (${#files[@]})" '[ ${#files[@]} -gt 100 ]'
# One clang-format process for all files (one per file spent 25 s starting up); it names each
# file that differs in its warnings ("FILE:LINE:COL: error: code should be clang-formatted").
rc=0
"$clang_format" --dry-run --Werror "${files[@]}" > "$scratch/format.txt" 2>&1 || rc=$?
mapfile -t bad < <(sed -nE 's/^([^:]+):[0-9]+:[0-9]+: (error|warning): code should be clang-formatted.*/\1/p' \
  "$scratch/format.txt" | sort -u)
# A failure without a layout warning is clang-format itself failing (a file it cannot read).
check "clang-format ran (exit $rc)" '[ $rc -eq 0 ] || [ ${#bad[@]} -gt 0 ] || { head "$scratch/format.txt"; false; }'
for f in "${bad[@]}"; do
  echo "-- $f differs from clang-format's layout:"
  "$clang_format" "$f" | diff -u "$f" - | sed -n 3,14p
done
check "every file as clang-format lays it out (${#bad[@]} not; fix: bash jobs/tools/format.sh)" \
  '[ ${#bad[@]} -eq 0 ]'
checks_done format
