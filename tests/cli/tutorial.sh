#!/usr/bin/env bash
# Requirement: every command of docs/tutorial.md runs as written. Its
# fenced blocks are taken in order and run in an empty folder that has the
# source tree's build/rpfem (this build's), python/ and scripts/:
#   ```sh             run with bash -e -o pipefail; a block whose first line
#                     is "# needs: CMD ..." is skipped (said so) where a CMD
#                     is not installed
#   ```toml FILE      written to FILE
#   ```python FILE    written to FILE, then run with /usr/bin/python3
# Other blocks (```text: output shown) are not run. Fails on the first
# block that fails, naming it and showing its output; fails too if the
# tutorial has no block to run (the fences' marks changed).
set -u
rpfem=$1; src=$2
doc="$src/docs/tutorial.md"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/work/build" "$tmp/blocks"
ln -s "$rpfem" "$tmp/work/build/rpfem"
ln -s "$src/python" "$tmp/work/python"
ln -s "$src/scripts" "$tmp/work/scripts"

# Split the tutorial into numbered blocks: blocks/NNN.KIND[.FILE].
awk -v dir="$tmp/blocks" '
  /^```/ {
    if (inside) { inside = 0; close(out); next }
    inside = 1; kind = substr($1, 4); name = $2
    if (kind != "sh" && kind != "toml" && kind != "python") { out = "/dev/null"; next }
    n++; out = sprintf("%s/%03d.%s%s", dir, n, kind, name == "" ? "" : "." name); printf "" > out; next
  }
  inside { print > out }
' "$doc"

count=0
for block in "$tmp"/blocks/*; do
  [ -e "$block" ] || break
  base=$(basename "$block"); kind=${base#*.}; file=${kind#*.}; kind=${kind%%.*}
  [ "$file" = "$kind" ] && file=""
  cd "$tmp/work"
  case $kind in
    toml)
      [ -n "$file" ] || { echo "FAIL: block $base: a toml block names its file"; exit 1; }
      cp "$block" "$file"; continue ;;
    python)
      [ -n "$file" ] || file="$base.py"
      cp "$block" "$file"
      cmd=(/usr/bin/python3 "$file") ;;
    sh)
      needs=$(head -1 "$block" | sed -n 's/^# needs: *//p')
      missing=""
      for c in $needs; do command -v "$c" > /dev/null || missing="$missing $c"; done
      if [ -n "$missing" ]; then echo "skipped: block $base (not installed:$missing)"; continue; fi
      cmd=(bash -e -o pipefail "$block") ;;
  esac
  # A virtual display that fails to start on a busy machine ("bad X server
  # connection", as in visualization.sh) is no fault of the tutorial's:
  # that alone is tried again.
  for attempt in 1 2 3; do
    "${cmd[@]}" > "$tmp/log" 2>&1 && ok=1 || ok=0
    [ $ok = 1 ] || ! grep -q "bad X server connection" "$tmp/log" && break
    echo "note: no virtual display for block $base (attempt $attempt), again"
  done
  if [ $ok = 0 ]; then
    echo "FAIL: docs/tutorial.md block $base:"; sed 's/^/  | /' "$block"; echo "output:"; tail -30 "$tmp/log"
    exit 1
  fi
  count=$((count + 1))
done
[ "$count" -gt 0 ] || { echo "FAIL: no block of docs/tutorial.md was run"; exit 1; }
echo "ok: $count blocks of docs/tutorial.md ran"
