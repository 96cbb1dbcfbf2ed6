#!/usr/bin/env bash
# check_links.sh on tests/docs/broken/, whose pages hold good references of every kind and four
# planted broken ones: it must exit 1 and name exactly those four.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
out=$(bash "$here/check_links.sh" "$here/broken")
rc=$?
expected="README.md:6: docs/sub/missing.txt: no such file or folder (path)
README.md:6: docs/missing.md: no such file or folder (link)
docs/page.md:3: ../nowhere.md: no such file or folder (link)
docs/page.md:6: docs/gone.json: no such file or folder (path)
check_links: 2 pages, 11 references, 4 missing"
if [[ $rc -ne 1 || "$out" != "$expected" ]]; then
  printf 'check_links.sh on the planted links: exit %d (want 1), output:\n%s\nwant:\n%s\n' "$rc" "$out" "$expected"
  exit 1
fi
echo "check_links.sh found the 4 planted broken references"
