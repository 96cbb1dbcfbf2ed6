#!/usr/bin/env bash
# Fails when README.md or docs/**/*.md names a file that does not exist: a relative markdown link
# (resolved from the page's folder; the #anchor is dropped) or a `docs/...` path in backquotes or
# a code block (resolved from the root; a glob, or a <placeholder> taken as *, must match something).
# docs/runs/ is raw command output, kept as printed, and is not read.
# usage: check_links.sh [ROOT]   (default: the source tree holding this script)
set -euo pipefail
root=${1:-$(cd "$(dirname "$0")/../.." && pwd)}
cd "$root"

pages=()
[[ -f README.md ]] && pages+=(README.md)
if [[ -d docs ]]; then
  while IFS= read -r p; do pages+=("$p"); done < <(find docs -path docs/runs -prune -o -name '*.md' -print | sort)
fi
(( ${#pages[@]} )) || { echo "check_links: no README.md or docs/*.md under $root"; exit 1; }

# One line per reference: page, line number, kind (link: relative to the page; path: to the root), target.
refs=$(awk '
  function emit(kind, t) { printf "%s\t%d\t%s\t%s\n", FILENAME, FNR, kind, t }
  function code_paths(s,   n, w, i, t) {
    n = split(s, w, /[ \t=(,;"]+/)
    for (i = 1; i <= n; ++i) if (w[i] ~ /^docs\//) { t = w[i]; sub(/[.,:;)]+$/, "", t); emit("path", t) }
  }
  FNR == 1 { fence = 0 }
  /^[ \t]*(```|~~~)/ { fence = !fence; next }
  fence { code_paths($0); next }
  {
    line = $0
    # inline code spans first, then links outside them
    rest = ""
    while (match(line, /`[^`]+`/)) {
      code_paths(substr(line, RSTART + 1, RLENGTH - 2))
      rest = rest substr(line, 1, RSTART - 1) " "
      line = substr(line, RSTART + RLENGTH)
    }
    line = rest line
    while (match(line, /\]\([^) \t]+( "[^"]*")?\)/)) {
      t = substr(line, RSTART + 2, RLENGTH - 3); sub(/ ".*/, "", t)
      line = substr(line, RSTART + RLENGTH)
      if (t ~ /^[a-zA-Z][a-zA-Z+.-]*:/ || t ~ /^#/) continue
      sub(/#.*/, "", t); gsub(/^<|>$/, "", t)
      emit("link", t)
    }
    if (match(line, /^[ \t]*\[[^]]+\]:[ \t]+[^ \t]+/)) {
      t = line; sub(/^[ \t]*\[[^]]+\]:[ \t]+/, "", t); sub(/[ \t].*/, "", t)
      if (t !~ /^[a-zA-Z][a-zA-Z+.-]*:/ && t !~ /^#/) { sub(/#.*/, "", t); emit("link", t) }
    }
  }' "${pages[@]}")

bad=0
checked=0
while IFS=$'\t' read -r page line kind target; do
  [[ -n $page ]] || continue
  if [[ $kind == link ]]; then path="$(dirname "$page")/$target"; else path=$target; fi
  checked=$((checked + 1))
  [[ $path == *'<'*'>'* ]] && path=$(sed 's/<[^>]*>/*/g' <<< "$path")
  if [[ $path == *[\*\?\[]* ]]; then
    compgen -G "$path" > /dev/null && continue
  elif [[ -e $path ]]; then
    continue
  fi
  echo "$page:$line: $target: no such file or folder ($kind)"
  bad=$((bad + 1))
done <<< "$refs"

echo "check_links: ${#pages[@]} pages, $checked references, $bad missing"
(( bad == 0 ))
