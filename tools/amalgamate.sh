#!/bin/sh
# Joins the library's parts, src/*.h in the order of src/parts.txt, into the one header
# users copy, revjoint.h. Each part opens with its banner, so the joined file reads as
# one written by hand: no markers, no #line. A part may open a block another closes (the
# implementation's #if opens in impl.h and closes in end.h; scene files' in scene_parse.h
# and scene_write.h).
#   sh tools/amalgamate.sh            write revjoint.h
#   sh tools/amalgamate.sh --check    exit 1 when revjoint.h is not what the parts give
cd "$(dirname "$0")/.." || exit 1
out=revjoint.h
tmp=$(mktemp) || exit 1
trap 'rm -f "$tmp"' EXIT
while read -r part; do
  [ -n "$part" ] || continue
  [ -f "src/$part" ] || { echo "amalgamate: src/parts.txt names src/$part, which does not exist" >&2; exit 1; }
  cat "src/$part" >> "$tmp"
done < src/parts.txt
# every part is listed once
for f in src/*.h; do
  n=$(grep -cx "$(basename "$f")" src/parts.txt)
  [ "$n" = 1 ] || { echo "amalgamate: $f is listed $n times in src/parts.txt" >&2; exit 1; }
done
if [ "$1" = "--check" ]; then
  if cmp -s "$tmp" "$out"; then echo "PASS revjoint.h is what src/ gives (tools/amalgamate.sh)"; exit 0; fi
  echo "FAIL revjoint.h differs from what src/ gives: edit src/, then run make (tools/amalgamate.sh)"
  exit 1
fi
cmp -s "$tmp" "$out" || cp "$tmp" "$out"
