#!/usr/bin/env bash
# Gets Debian's POV-Ray 3.7.0.10 source with `apt-get source` through a private apt
# configuration (a deb-src entry for the mirror of /etc/apt/sources.list.d/debian.sources, with
# its own lists and cache under WORK; the system's apt state is never written), unpacks it with
# Debian's patch series applied (dpkg-source), applies Facet's series (PATCH_DIR/*.patch, in
# name order, by apply_series.sh), and configures it the way debian/rules does.
# Usage: prepare_source.sh WORK PATCH_DIR BRIDGE_DIR
# Re-running starts from a fresh unpack (the download is kept).
set -euo pipefail
work="$1" patch_dir="$2" bridge_dir="$3"
version="1:3.7.0.10-2"
mkdir -p "$work"
work="$(cd "$work" && pwd)"
apt_dir="$work/apt"

# --- private apt configuration ---------------------------------------------------------------
mirror="$(sed -n 's/^URIs: *//p' /etc/apt/sources.list.d/debian.sources 2>/dev/null | head -n1)"
[ -n "$mirror" ] || mirror="http://deb.debian.org/debian"
mkdir -p "$apt_dir/sources.list.d" "$apt_dir/lists/partial" "$apt_dir/cache/archives/partial"
cat > "$apt_dir/sources.list.d/povray-src.sources" <<SRC
Types: deb-src
URIs: $mirror
Suites: bookworm
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
SRC
cat > "$apt_dir/apt.conf" <<CONF
Dir::Etc::sourcelist "/dev/null";
Dir::Etc::sourceparts "$apt_dir/sources.list.d";
Dir::State::lists "$apt_dir/lists";
Dir::Cache "$apt_dir/cache";
APT::Sandbox::User "root";
CONF
export APT_CONFIG="$apt_dir/apt.conf"

dl="$work/download"
mkdir -p "$dl"
if ! ls "$dl"/povray_3.7.0.10-2.dsc > /dev/null 2>&1; then
  echo "povray-facet: apt-get source povray=$version (private apt configuration $APT_CONFIG)"
  apt-get -q update > "$work/apt-update.log" 2>&1 || { cat "$work/apt-update.log"; exit 1; }
  (cd "$dl" && apt-get -q source --download-only "povray=$version")
fi

# --- unpack (Debian's series is applied by dpkg-source for a 3.0 (quilt) package) ------------
src="$work/src"
rm -rf "$src"
dpkg-source -x "$dl/povray_3.7.0.10-2.dsc" "$src" > "$work/unpack.log"
patches=()
while IFS= read -r p; do patches+=("$p"); done < <(find "$patch_dir" -maxdepth 1 -name '*.patch' | LC_ALL=C sort)
[ "${#patches[@]}" -gt 0 ] || { echo "povray-facet: no *.patch in $patch_dir" >&2; exit 1; }
"$(dirname "$0")/apply_series.sh" "$src" "${patches[@]}"

# --- configure as debian/rules does ----------------------------------------------------------
cd "$src"
(cd unix/config && for ax in *.m4; do
  if [ ! -h "$ax" ] && [ -f "/usr/share/aclocal/$ax" ]; then
    mv "$ax" "$ax.dist"
    ln -s "/usr/share/aclocal/$ax"
  fi
done)
if [ -d libraries ] && [ ! -d libraries.donotuse ]; then mv libraries libraries.donotuse; fi
(cd unix && ./prebuild.sh > "$work/prebuild.log" 2>&1) || { tail -n 40 "$work/prebuild.log"; exit 1; }
autoreconf -f -i > "$work/autoreconf.log" 2>&1   # dh_autoreconf (debhelper compat 13)
export DEB_BUILD_MAINT_OPTIONS="hardening=+all"
# Debian's flags less -g: debug information never changes the generated code (GCC's rule; the
# .text of backend/render/trace.cpp is byte-identical with and without it), and leaving it out
# saves about a fifth of POV-Ray's compile time.
cxxflags="$(dpkg-buildflags --get CXXFLAGS | sed -E 's/(^| )-g( |$)/ /') -O3"
ldflags="$(dpkg-buildflags --get LDFLAGS)"
cppflags="$(dpkg-buildflags --get CPPFLAGS) -I$bridge_dir"
cxx="g++"
if command -v ccache > /dev/null; then cxx="ccache g++"; fi
# dh_auto_configure's arguments, less --disable-dependency-tracking (kept for rebuilds) and the
# silent rules; the COMPILED_BY string names this build.
./configure --build=x86_64-linux-gnu --prefix=/usr --includedir='${prefix}/include' \
  --mandir='${prefix}/share/man' --infodir='${prefix}/share/info' --sysconfdir=/etc \
  --localstatedir=/var --disable-option-checking --libdir='${prefix}/lib/x86_64-linux-gnu' \
  --runstatedir=/run --disable-maintainer-mode \
  --disable-optimiz --disable-strip --with-boost-thread=boost_thread \
  COMPILED_BY="Facet povray-facet (Debian 3.7.0.10-2 + Facet patch)" \
  CXX="$cxx" CXXFLAGS="$cxxflags" CPPFLAGS="$cppflags" LDFLAGS="$ldflags" \
  > "$work/configure.log" 2>&1 || { tail -n 40 "$work/configure.log"; exit 1; }
sed -i '/CXXFLAGS/s/ -ffile-prefix-map=[^ ]* / /' unix/config.h
echo "povray-facet: source configured in $src"
