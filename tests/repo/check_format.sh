#!/usr/bin/env bash
# Every C++ source of the repository is formatted by .clang-format (clang-format from Debian 12).
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
cd "$top"
if git rev-parse --git-dir >/dev/null 2>&1; then
  mapfile -t files < <(git ls-files '*.cpp' '*.hpp')
else
  mapfile -t files < <(find . -path ./build -prune -o \( -name '*.cpp' -o -name '*.hpp' \) -print)
fi
if ! out=$(clang-format --dry-run -Werror "${files[@]}" 2>&1); then
  echo "$out" | grep -E "error:" | head -40
  echo "check_format: not formatted (fix: clang-format -i FILE, or git clang-format)" >&2
  exit 1
fi
echo "check_format: ${#files[@]} files formatted"
