#!/usr/bin/env bash
# Command 1 of the README: install dependencies, build everything (Release) and run the main
# job — render the showcase scene into out/.
set -euo pipefail
cd "$(dirname "$0")"
tools/deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"
mkdir -p out
build/core/cli/facet render scenes/showcase.json -o out/showcase_facet.exr -o out/showcase_facet.png
build/core/cli/facet brdf plot --model ggx --alpha 0.3 --theta 45 -o out/ggx_lobe.png
# The second showcase (tools/make_showcase_media.py): subsurface scattering, a liquid in glass,
# hair and a lamp's beam through fog.
build/core/cli/facet render scenes/showcase_media.json -o out/showcase_media_facet.exr \
  -o out/showcase_media_facet.png
# The same showcase inside headless Blender with the Facet addon (installed from the zip into a
# user scripts directory in the build tree, not the user's own Blender configuration).
if [ -f build/blender_addon/facet_blender.zip ] && command -v blender > /dev/null; then
  BLENDER_USER_SCRIPTS="$PWD/build/blender_user/scripts" BLENDER_USER_CONFIG="$PWD/build/blender_user/config" \
    blender -b --factory-startup -noaudio --python blender_addon/render_json.py -- \
    build/blender_addon/facet_blender.zip scenes/showcase.json out/showcase_blender.exr out/showcase_blender.png
fi
# The showcase's POV-Ray equivalent (scenes/pov/showcase.pov, brdf finishes) with povray-facet.
if [ -x build/povray_patch/bin/povray-facet ]; then
  (cd out && ../build/povray_patch/bin/povray-facet +I../scenes/pov/showcase.pov +L../scenes/pov \
     +Oshowcase_povray.png +W960 +H540 +FN8 -D -V +A0.1 +AM2 +R2 Declare=Glossy_Samples=32 \
     2> showcase_povray.log) \
    || { tail -n 20 out/showcase_povray.log; exit 1; }
fi
# A JSON scene through `facet export-pov` into povray-facet (the Cornell box: its light becomes
# 8 x 8 cos-weighted light cells; the showcase has an environment light and an anisotropic
# lobe, which POV-Ray cannot express, so it uses the hand-written SDL above).
if [ -x build/povray_patch/bin/povray-facet ]; then
  build/core/cli/facet export-pov scenes/cornell_box.json -o out/cornell_box.pov --area-grid 8
  (cd out && ../build/povray_patch/bin/povray-facet +Icornell_box.pov +Ocornell_box_povray.exr \
     +FE +W512 +H512 -A -UA -D -V 2> cornell_box_povray.log) \
    || { tail -n 20 out/cornell_box_povray.log; exit 1; }
  build/core/cli/facet convert out/cornell_box_povray.exr -o out/cornell_box_povray.png
fi
echo "build.sh: done; images in out/"
