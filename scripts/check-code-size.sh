#!/usr/bin/env bash
# The size rules of docs/development.md: no .cpp over 1,000 lines, no function over 120 lines
# (the ray kernels TraceBlock and KernelAvx512 excepted: one tight loop each, kept whole for the
# compiler). Function extents come from Universal Ctags (its `end` field). Exit 1 listing every
# offender; run from anywhere.
set -euo pipefail
cd "$(dirname "$0")/.."
max_file=1000
max_function=120
exempt='^(TraceBlock|KernelAvx512)$'
command -v ctags >/dev/null || { echo "check-code-size: error: universal-ctags is not installed" >&2; exit 2; }
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  mapfile -t files < <(git ls-files '*.cpp' '*.h' | grep -v '^tests/')
else  # a source tree without git: every source outside tests/ and build folders
  mapfile -t files < <(find . -name '*.cpp' -o -name '*.h' | sed 's|^\./||' |
                       grep -vE '^(tests|build[^/]*)/' | sort)
fi
bad=0
for f in "${files[@]}"; do
  [[ $f == *.cpp ]] || continue
  n=$(wc -l < "$f")
  if (( n > max_file )); then echo "$f: $n lines (at most $max_file)"; bad=1; fi
done
while read -r start end name file; do
  [[ $name =~ $exempt || $name == __anon* ]] && continue
  len=$((end - start + 1))
  if (( len > max_function )); then echo "$file:$start: $name is $len lines (at most $max_function)"; bad=1; fi
done < <(ctags -x --kinds-c++=f --fields=+ne --_xformat="%{line} %{end} %{name} %{input}" "${files[@]}")
if (( bad )); then exit 1; fi
echo "check-code-size: every .cpp at most $max_file lines, every function at most $max_function"
