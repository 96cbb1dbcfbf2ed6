#!/usr/bin/env bash
# Fails when README.md or docs/**/*.md names a file that does not exist: a relative markdown link
# (resolved from the page's folder) or a path in backquotes or a code block under docs/, or, outside
# docs/history/, under bench/, src/, include/, tests/, apps/, scripts/, cmake/ or .ci/ (resolved from
# the root; a glob, or a <placeholder> or {a,b} taken as *, must match something); or when a link's
# #anchor (`page.md#anchor`, or `#anchor` on the same page) names no heading of that .md page.
# docs/runs/ is raw command output, kept as printed, and is not read; docs/history/ quotes commands
# as they were run, so only its docs/ paths are checked.
# usage: check_links.sh [ROOT]   (default: the source tree holding this script)
set -euo pipefail
export LC_ALL=C  # awk works on bytes; the slugs decode UTF-8 themselves
root=${1:-$(cd "$(dirname "$0")/../.." && pwd)}
cd "$root"

pages=()
[[ -f README.md ]] && pages+=(README.md)
if [[ -d docs ]]; then
  while IFS= read -r p; do pages+=("$p"); done < <(find docs -path docs/runs -prune -o -name '*.md' -print | sort)
fi
(( ${#pages[@]} )) || { echo "check_links: no README.md or docs/*.md under $root"; exit 1; }

# One line per reference, fields split by \037 (an empty one survives): page, line number, kind
# (link: relative to the page; path: to the root), target, anchor (without the #).
refs=$(awk '
  function emit(kind, t,   a) {
    a = ""; if (kind == "link" && match(t, /#/)) { a = substr(t, RSTART + 1); t = substr(t, 1, RSTART - 1) }
    printf "%s\037%d\037%s\037%s\037%s\n", FILENAME, FNR, kind, t, a
  }
  function code_paths(s,   n, w, i, t) {
    n = split(s, w, /[ \t=(,;"]+/)
    for (i = 1; i <= n; ++i)
      if (w[i] ~ /^docs\// || (!history && w[i] ~ /^(bench|src|include|tests|apps|scripts|cmake|\.ci)\//)) {
        t = w[i]; sub(/[.,:;)]+$/, "", t); emit("path", t)
      }
  }
  FNR == 1 { fence = 0; history = FILENAME ~ /^docs\/history\// }
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
      if (t ~ /^[a-zA-Z][a-zA-Z+.-]*:/) continue
      gsub(/^<|>$/, "", t)
      emit("link", t)
    }
    if (match(line, /^[ \t]*\[[^]]+\]:[ \t]+[^ \t]+/)) {
      t = line; sub(/^[ \t]*\[[^]]+\]:[ \t]+/, "", t); sub(/[ \t].*/, "", t)
      if (t !~ /^[a-zA-Z][a-zA-Z+.-]*:/) emit("link", t)
    }
  }' "${pages[@]}")

# The anchors GitHub gives the headings of markdown FILE, one a line: the heading's text without its
# markup, lowercased; letters, marks, decimal digits, "_", "-" kept, spaces turned to "-", every other
# character dropped (punctuation, symbols, and other numbers such as the "2" of "4096\302\262"); a repeat
# gets -1, -2 (as github-slugger, whose fixtures are GitHub's own output). Non-ASCII characters are
# classed by code-point range: one outside the ranges below stops the check rather than be guessed.
slugs() {
  awk '
    BEGIN { for (i = 1; i < 256; ++i) { ch = sprintf("%c", i); ord[ch] = i; chr[i] = ch } }
    function utf8(c) {
      if (c < 128) return chr[c]
      if (c < 2048) return chr[192 + int(c / 64)] chr[128 + c % 64]
      if (c < 65536) return chr[224 + int(c / 4096)] chr[128 + int(c / 64) % 64] chr[128 + c % 64]
      return chr[240 + int(c / 262144)] chr[128 + int(c / 4096) % 64] chr[128 + int(c / 64) % 64] chr[128 + c % 64]
    }
    # the lowercase of letter c, or -1 when c is no letter, mark or decimal digit (then it is dropped)
    function keep(c) {
      if (c == 170 || c == 181 || c == 186 || (c >= 223 && c <= 255 && c != 247)) return c
      if (c >= 192 && c <= 222 && c != 215) return c + 32                       # Latin-1 capitals
      if (c >= 160 && c <= 191 || c == 215 || c == 247) return -1               # Latin-1 signs, ¹²³¼½¾
      if (c >= 256 && c <= 311 || c >= 330 && c <= 375) return c + (c % 2 == 0) # Latin Extended-A pairs
      if (c >= 313 && c <= 328 || c >= 377 && c <= 382) return c + (c % 2 == 1)
      if (c == 312 || c == 329 || c >= 383 && c <= 879) return c                # Latin Ext-B, IPA, marks
      if (c == 376) return 255
      if (c >= 913 && c <= 939 && c != 930) return c + 32                       # Greek capitals
      if (c == 885 || c == 894 || c == 900 || c == 901 || c == 903 || c == 1014) return -1
      if (c >= 880 && c <= 1023) return c                                        # Greek (no accented capitals)
      if (c >= 1040 && c <= 1071) return c + 32                                 # Cyrillic capitals
      if (c >= 1024 && c <= 1039) return c + 80
      if (c == 1154) return -1
      if (c >= 1072 && c <= 1279) return c
      if (c >= 8192 && c <= 8303) return (c == 8255 || c == 8256 || c == 8276) ? c : -1 # punctuation; ‿⁀⁔ join
      if (c >= 8304 && c <= 8348) return (c == 8305 || c == 8319 || c >= 8336) ? c : -1 # super/subscripts
      if (c >= 8352 && c <= 8399) return -1                                      # currency
      if (c >= 8592 && c <= 9311 || c >= 9472 && c <= 11263) return -1           # arrows, math, boxes, symbols
      if (c == 12539 || c == 12448) return -1                                    # ・ ゠
      if (c >= 12352 && c <= 12543 || c >= 13312 && c <= 40959 || c >= 44032 && c <= 55203) return c # kana, Han, Hangul
      if (c >= 126976 && c <= 127231 || c >= 127744 && c <= 129791) return -1    # mahjong, cards, emoji
      return -2
    }
    function slug(s,   out, i, n, b, c, k, len) {
      gsub(/!?\[/, "", s); gsub(/\]\([^)]*\)/, "", s)     # [text](url) -> text
      gsub(/<[^>]*>/, "", s); gsub(/&#?[a-zA-Z0-9]+;/, "", s) # inline HTML, entities
      s = tolower(s); out = ""; n = length(s)
      for (i = 1; i <= n; i += len) {
        b = ord[substr(s, i, 1)]; len = 1
        if (b < 128) {
          if (substr(s, i, 1) ~ /[a-z0-9_-]/) out = out substr(s, i, 1); else if (b == 32) out = out "-"
          continue
        }
        if (b >= 240) { len = 4; c = b - 240 } else if (b >= 224) { len = 3; c = b - 224 } else { len = 2; c = b - 192 }
        for (k = 1; k < len; ++k) c = c * 64 + ord[substr(s, i + k, 1)] - 128
        k = keep(c)
        if (k == -2) { printf "check_links: %s:%d: cannot slug U+%04X in a heading; teach slugs() its class\n", FILENAME, FNR, c > "/dev/stderr"; failed = 1; exit 2 }
        if (k >= 0) out = out utf8(k)
      }
      return out
    }
    function emit(text,   s, base) {
      sub(/^[ \t]+/, "", text); sub(/[ \t]+#+[ \t]*$/, "", text); sub(/^#+[ \t]*$/, "", text); sub(/[ \t]+$/, "", text)
      s = base = slug(text)
      while (s in seen) s = base "-" (++seen[base])
      seen[s] = 0; print s
    }
    /^[ \t]*(```|~~~)/ { fence = !fence; prev = ""; next }
    fence { next }
    # (mawk has no {m,n}: "up to 3 spaces" is " ? ? ?", and 7 #s make no heading)
    /^ ? ? ?#+([ \t]|$)/ && !/^ *#######/ { t = $0; sub(/^ *#+/, "", t); emit(t); prev = ""; next }
    /^ ? ? ?(=+|-+)[ \t]*$/ && prev != "" { emit(prev); prev = ""; next }    # setext heading
    { prev = ($0 ~ /^[ \t]*$/ || $0 ~ /^ ? ? ?([-*+>|]|[0-9]+[.)])/) ? "" : $0 }
    { while (match($0, /<a (name|id)="[^"]+"/)) { t = substr($0, RSTART, RLENGTH); sub(/^[^"]*"/, "", t); print substr(t, 1, length(t) - 1); $0 = substr($0, RSTART + RLENGTH) } }
    END { exit failed ? 2 : 0 }' "$1"
}

declare -A anchors_of
bad=0
checked=0
while IFS=$'\037' read -r page line kind target anchor; do
  [[ -n $page ]] || continue
  checked=$((checked + 1))
  if [[ $kind == link && -z $target ]]; then
    path=$page
  elif [[ $kind == link ]]; then
    path="$(dirname "$page")/$target"
  else
    path=$target
  fi
  [[ $path == *'<'*'>'* ]] && path=$(sed 's/<[^>]*>/*/g' <<< "$path")
  [[ $path == *'{'* ]] && path="${path%%\{*}*"  # a{b,c}d, split at the comma: a*
  if [[ $path == *[\*\?\[]* ]]; then
    compgen -G "$path" > /dev/null && continue
  elif [[ -e $path ]]; then
    # only a markdown page's anchors are known; a folder's or another file's are not checked
    [[ -z $anchor || -d $path || $path != *.md ]] && continue
    [[ -v "anchors_of[$path]" ]] || anchors_of[$path]=$(slugs "$path") || exit 2
    grep -qxF -- "$anchor" <<< "${anchors_of[$path]}" && continue
    echo "$page:$line: $target#$anchor: no heading with that anchor in ${path#./}"
    bad=$((bad + 1))
    continue
  fi
  echo "$page:$line: $target: no such file or folder ($kind)"
  bad=$((bad + 1))
done <<< "$refs"

echo "check_links: ${#pages[@]} pages, $checked references, $bad broken"
(( bad == 0 ))
