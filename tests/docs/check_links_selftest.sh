#!/usr/bin/env bash
# check_links.sh on tests/docs/broken/, whose pages hold good references of every kind (anchors
# included: a repeated heading, a dropped "²", an <a name>, a setext heading; a source path and a
# {a,b} brace; source paths in docs/history/, which are not checked) and eight planted broken ones:
# it must exit 1 and name exactly those eight.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
out=$(bash "$here/check_links.sh" "$here/broken")
rc=$?
expected="README.md:6: docs/sub/missing.txt: no such file or folder (path)
README.md:6: docs/missing.md: no such file or folder (link)
README.md:8: src/gone.cpp: no such file or folder (path)
README.md:12: docs/page.md#4096²-rays--x_y: no heading with that anchor in docs/page.md
README.md:12: docs/page.md#a-2: no heading with that anchor in docs/page.md
README.md:12: #nowhere: no heading with that anchor in README.md
docs/page.md:3: ../nowhere.md: no such file or folder (link)
docs/page.md:6: docs/gone.json: no such file or folder (path)
check_links: 3 pages, 22 references, 8 broken"
if [[ $rc -ne 1 || "$out" != "$expected" ]]; then
  printf 'check_links.sh on the planted links: exit %d (want 1), output:\n%s\nwant:\n%s\n' "$rc" "$out" "$expected"
  exit 1
fi
echo "check_links.sh found the 8 planted broken references"
