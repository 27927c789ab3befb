#!/usr/bin/env bash
# Developer helper: writes facet.patch as the difference between a pristine unpack of Debian's
# source (Debian's series applied) and a work tree holding Facet's changes.
# Usage: make_patch.sh PRISTINE_TREE WORK_TREE > povray_patch/facet.patch
set -uo pipefail
cd "$(dirname "$1")"
a="$(basename "$1")" b="$2"
diff -ruN -x '*.o' -x '*.a' -x '.deps' -x 'Makefile' -x 'Makefile.in' -x 'Makefile.am' \
  -x 'config.*' -x 'configure' -x 'autom4te.cache' -x '*.orig' -x '.pc' -x 'povray' \
  "$a/source" "$b/source" | sed -e "s|^--- $a/|--- a/|" -e "s|^+++ $b/|+++ b/|"
diff -ruN "$a/unix/prebuild.sh" "$b/unix/prebuild.sh" \
  | sed -e "s|^--- $a/|--- a/|" -e "s|^+++ $b/|+++ b/|"
exit 0
