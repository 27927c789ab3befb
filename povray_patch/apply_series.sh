#!/usr/bin/env bash
# Applies Facet's patches to an unpacked POV-Ray tree, in the order given (prepare_source.sh
# passes patches/*.patch sorted by name). No fuzz: a patch that no longer fits its base fails
# here, naming the patch, rather than applying somewhere else.
# Usage: apply_series.sh TREE PATCH...
set -euo pipefail
tree="$1"
shift
for p in "$@"; do
  echo "povray-facet: applying $(basename "$p")"
  patch -p1 -s --fuzz=0 --no-backup-if-mismatch -d "$tree" < "$p" \
    || { echo "povray-facet: $p does not apply to $tree" >&2; exit 1; }
done
