#!/usr/bin/env bash
# Installs Facet's build and test dependencies from Debian 12's packages (idempotent: does
# nothing when they are all present). Needs root (or sudo) and the Debian package registry.
set -euo pipefail
packages=(
  build-essential cmake ninja-build ccache pkg-config git
  libglm-dev libembree-dev libtbb-dev libgtest-dev libgmock-dev libbenchmark-dev
  nlohmann-json3-dev libtinyobjloader-dev libopenexr-dev libstb-dev libcli11-dev libfmt-dev
  # images and textures (OpenImageIO: EXR, HDR, PNG, JPEG, TGA, TIFF; its TextureSystem), glTF,
  # OpenVDB grids (grid media)
  libopenimageio-dev openimageio-tools libtinygltf-dev libopenvdb-dev
  # real assets nobody here made: glTF models (and malformed ones) for the import tests
  assimp-testmodels
  libpcg-cpp-dev libboost-dev clang libclang-rt-14-dev python3
  # the facet Python module (built against Debian's /usr/bin/python3, the one Blender embeds)
  python3-dev pybind11-dev python3-numpy python3-pytest
  # povray-facet (povray_patch/): the stock POV-Ray and its example scenes as the reference of
  # the `povray` tests, dpkg-dev and patch for `apt-get source`, and POV-Ray's build-deps as
  # Debian's debian/control lists them (libsdl-dev is provided by libsdl1.2-dev on bookworm;
  # debhelper brings autoconf, automake and dh-autoreconf)
  povray povray-examples povray-includes dpkg-dev patch xz-utils
  debhelper autoconf-archive libpng-dev zlib1g-dev libx11-dev libxt-dev libice-dev
  libjpeg-dev libtiff-dev libboost-thread-dev libsdl1.2-dev libxpm-dev autoconf automake
  # the Blender addon and its tests: Debian's Blender 3.4.1 (embeds /usr/bin/python3 3.11 and
  # loads the system Embree/TBB; ~32 s to install here) run headless (`blender -b`), and Xvfb
  # for the viewport tests
  blender xvfb xauth
  # facet-farm, distributed rendering (facet.farm): Dask's scheduler, workers and LocalCluster
  python3-distributed
  # bench/time_error.py: the log-log plots of error against time
  python3-matplotlib
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "deps: installing ${missing[*]}"
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
