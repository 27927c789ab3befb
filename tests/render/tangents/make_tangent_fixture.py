"""Blender's own MikkTSpace tangents as a test fixture (tests/render/test_normal_maps.cpp).

Run with Blender (3.4.1 made the checked-in file), from the checkout's root:
    blender -b --factory-startup --python tests/render/tangents/make_tangent_fixture.py -- \
        tests/render/tangents/blender_tangents.json

Three smooth-shaded, triangulated meshes, each written per triangle corner (loop) in triangle
order: object-space position, loop normal, UV, and Mesh.calc_tangents()' tangent and
bitangent sign:
  - uv_sphere: the UV sphere primitive (16 segments, 8 rings) with its own UVs: a seam at u = 0
    and triangles meeting at the poles with different UVs;
  - mirrored_grid: a displaced 6 x 6 grid whose UVs mirror across x = 0 (u = |x|), so that the
    vertices on x = 0 are shared by triangles of both UV orientations (tangent sign +1 and -1);
  - cube: the cube primitive's UV layout (islands with seams), smooth shaded.
"""
import json
import math
import sys

import bmesh
import bpy


def triangulated(obj):
    me = obj.data
    bm = bmesh.new()
    bm.from_mesh(me)
    bmesh.ops.triangulate(bm, faces=bm.faces[:])
    bm.to_mesh(me)
    bm.free()
    for p in me.polygons:
        p.use_smooth = True
    return me


def corners(me):
    me.calc_tangents(uvmap=me.uv_layers.active.name)
    uv = me.uv_layers.active.data
    out = {"positions": [], "normals": [], "uvs": [], "tangents": []}
    for poly in me.polygons:
        assert poly.loop_total == 3
        for li in poly.loop_indices:
            loop = me.loops[li]
            out["positions"] += list(me.vertices[loop.vertex_index].co)
            out["normals"] += list(loop.normal)
            out["uvs"] += list(uv[li].uv)
            out["tangents"] += list(loop.tangent) + [loop.bitangent_sign]
    return out


def main():
    path = sys.argv[sys.argv.index("--") + 1]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    meshes = {}

    bpy.ops.mesh.primitive_uv_sphere_add(segments=16, ring_count=8, radius=1.0)
    meshes["uv_sphere"] = corners(triangulated(bpy.context.active_object))

    bpy.ops.mesh.primitive_grid_add(x_subdivisions=6, y_subdivisions=6, size=2.0)
    obj = bpy.context.active_object
    me = obj.data
    for v in me.vertices:
        v.co.z = 0.2 * math.sin(2.0 * v.co.x) * math.cos(3.0 * v.co.y)
    me = triangulated(obj)
    uv = me.uv_layers.active.data
    for poly in me.polygons:
        for li in poly.loop_indices:
            co = me.vertices[me.loops[li].vertex_index].co
            uv[li].uv = (abs(co.x), 0.5 * (co.y + 1.0))
    meshes["mirrored_grid"] = corners(me)

    bpy.ops.mesh.primitive_cube_add(size=2.0)
    meshes["cube"] = corners(triangulated(bpy.context.active_object))

    with open(path, "w") as f:
        json.dump({"generator": "make_tangent_fixture.py, Blender " + bpy.app.version_string,
                   "meshes": meshes}, f)
        f.write("\n")


if __name__ == "__main__":
    main()
