"""Not one silent drop (issue 35): every Blender object type, the render, Cycles, view layer
and world settings, the objects', lamps' and collections' visibility flags, particle hair and a
volume-only material are either converted or named in the render's report.

The walk is over Blender's own RNA properties, not over the addon's tables: a property in none
of gaps.py's tables (a row removed, or a new Blender setting) fails, and so does a reported row
whose setting gives no line when set away from its default, or a converted one whose export
does not change. Object types are checked against this file's own expectations, so a missing
OBJECT_TYPES row (the exporter's generic line instead of the type's) fails too."""
import os
import sys

import bpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402

# Object type -> "shape" / "light" (converted: the export gains one), a phrase of its report
# line, or None (Cycles renders nothing of it either, or Blender draws it itself: no line).
EXPECT_TYPES = {
    'MESH': "shape", 'CURVE': "shape", 'SURFACE': "shape", 'META': "shape", 'FONT': "shape",
    'LIGHT': "light",
    # Converted (sync_hair.py); an empty one (no curves) renders nothing, with a line.
    'CURVES': "hair curves with no curves; skipped",
    'POINTCLOUD': "point clouds are not in Facet's core",
    # Converted (sync_volume.py); an empty one (no grids) renders nothing, with a line.
    'VOLUME': "volume has no grids; not rendered",
    'GPENCIL': None, 'EMPTY': None, 'ARMATURE': None, 'LATTICE': None, 'LIGHT_PROBE': None,
    'SPEAKER': None, 'CAMERA': None,
}

# Converted settings that act only with another one set first (path -> {path: value}).
PREREQ = {
    "render.use_border": {"render.border_max_x": 0.5},
    "render.border_min_x": {"render.use_border": True},
    "render.border_min_y": {"render.use_border": True},
    "render.border_max_x": {"render.use_border": True},
    "render.border_max_y": {"render.use_border": True},
    "render.motion_blur_shutter": {"render.use_motion_blur": True},
    "cycles.motion_blur_position": {"render.use_motion_blur": True},
    "view_layer.use_motion_blur": {"render.use_motion_blur": True},
    # Reported only with Film > Transparent on.
    "cycles.film_transparent_glass": {"render.film_transparent": True},
}


def fresh():
    scene = bt.factory_scene(64, 36)
    return scene


def export():
    from facet_blender import export as ex
    data, problems = ex.export_scene(bpy.context.evaluated_depsgraph_get())
    return data, problems


def fingerprint():
    """What the render is made of, without the mesh arrays: camera, shape kinds, materials,
    lights, render settings, holdouts, shadow catchers, ray visibility, Light Path switches,
    the render region and the Shadow Catcher pass (which changes the Combined pass)."""
    from facet_blender import export as ex, passes, pixels
    data, problems = export()
    scene = bpy.context.scene
    w, h = ex.resolution(scene)
    shapes = [(s["type"], s.get("name"), s.get("material"), s.get("holdout", False),
               s.get("shadow_catcher", False), sorted((s.get("visibility") or {}).items()),
               s.get("light_path"))
              for s in data["shapes"]]
    return repr((data["camera"], shapes, data["lights"], data["materials"], data["render"],
                 pixels.border_rect(scene.render, w, h),
                 passes.shadow_catcher_pass(bpy.context.view_layer))), problems


def roots(scene):
    """Path prefix -> the struct the walk reads (the view layer's, world's and colour
    management's too)."""
    vl = bpy.context.view_layer
    return {"render": scene.render, "cycles": scene.cycles, "cycles_curves": scene.cycles_curves,
            "view_layer": vl, "view_layer.cycles": vl.cycles, "world.cycles": scene.world.cycles,
            "world.cycles_visibility": scene.world.cycles_visibility,
            "world.light_settings": scene.world.light_settings,
            "view_settings": scene.view_settings, "display_settings": scene.display_settings}


def resolve(path):
    """(struct, attribute) of a scene-level path ("view_layer." from the view layer)."""
    scene = bpy.context.scene
    parts = path.split(".")
    obj = bpy.context.view_layer if parts[0] == "view_layer" else scene
    for part in parts[1 if parts[0] == "view_layer" else 0:-1]:
        obj = getattr(obj, part)
    return obj, parts[-1]


def walked(struct):
    """The writable properties of a struct the walk sets: (identifier, RNA property)."""
    out = []
    for p in struct.bl_rna.properties:
        if p.identifier in ("rna_type", "name") or p.is_readonly or p.type == 'COLLECTION':
            continue
        out.append((p.identifier, p))
    return out


def away(struct, attr, prop, quiets=None, owner=None):
    """A value of `attr` away from its current one (and from the quiet values)."""
    from facet_blender import gaps
    v = getattr(struct, attr)
    if prop.type == 'BOOLEAN' and getattr(prop, "array_length", 0) == 0:
        cands = [not v]
    elif prop.type == 'ENUM':
        cands = [i.identifier for i in prop.enum_items if i.identifier != v]
    elif prop.type == 'INT' and getattr(prop, "array_length", 0) == 0:
        cands = [x for x in (v - 1, v + 1, v + 5) if prop.hard_min <= x <= prop.hard_max]
    elif prop.type == 'FLOAT' and getattr(prop, "array_length", 0) == 0:
        cands = [x for x in (v + 0.5, v - 0.5, v * 0.5, (prop.hard_min + prop.hard_max) / 2)
                 if prop.hard_min <= x <= prop.hard_max and x != v]
    elif prop.type == 'POINTER':
        if prop.fixed_type.identifier == 'Material':
            cands = [bpy.data.materials.new("override")]
        elif prop.fixed_type.identifier == 'Object':
            cands = [bpy.data.objects["Camera"]]
        else:
            cands = []
    else:
        return None  # arrays, strings: classified, not set
    for c in cands:
        if quiets is None or not gaps.quiet(c, quiets, owner):
            return c
    return None


def reported_row(table, path):
    return next(r for r in table if r[0] == path)


def check_classified(paths):
    from facet_blender import gaps
    missing = [p for p in paths if not gaps.classify(p)]
    bt.check(not missing, "every walked setting is reported, converted or unchanged by gaps.py "
             "(%d walked); in no table: %s" % (len(paths), missing))


def case_object_types():
    from facet_blender import gaps
    types = [i.identifier for i in bpy.types.Object.bl_rna.properties['type'].enum_items]
    bt.check(sorted(types) == sorted(EXPECT_TYPES),
             "this test knows every object type of this Blender: %s" % types)
    makers = {
        'MESH': lambda: _mesh(),
        'CURVE': lambda: _curve(),
        'SURFACE': lambda: _op(lambda: bpy.ops.surface.primitive_nurbs_surface_sphere_add()),
        'META': lambda: _op(lambda: bpy.ops.object.metaball_add()),
        'FONT': lambda: _op(lambda: bpy.ops.object.text_add()),
        'LIGHT': lambda: _point_lamp(),
        'CURVES': lambda: bpy.data.hair_curves.new("x"),
        'POINTCLOUD': lambda: bpy.data.pointclouds.new("x"),
        'VOLUME': lambda: bpy.data.volumes.new("x"),
        'GPENCIL': lambda: bpy.data.grease_pencils.new("x"),
        'EMPTY': lambda: None,
        'ARMATURE': lambda: bpy.data.armatures.new("x"),
        'LATTICE': lambda: bpy.data.lattices.new("x"),
        'LIGHT_PROBE': lambda: bpy.data.lightprobes.new("x", 'CUBE'),
        'SPEAKER': lambda: bpy.data.speakers.new("x"),
        'CAMERA': lambda: bpy.data.cameras.new("x"),
    }
    for t in types:
        scene = fresh()
        base, _ = export()
        made = makers[t]()
        if isinstance(made, bpy.types.Object):
            ob = made
        else:
            ob = bpy.data.objects.new("Typed", made)
            scene.collection.objects.link(ob)
        ob.name = "Typed"
        ob.location = (0.0, 0.0, 0.0)
        bt.check(ob.type == t, "made a %s object" % t)
        data, problems = export()
        mine = [p for p in problems if "'Typed'" in p]
        want = EXPECT_TYPES[t]
        if want == "shape":
            bt.check(len(data["shapes"]) > len(base["shapes"]) and not mine,
                     "%s: converted (%d -> %d shapes), no line: %s"
                     % (t, len(base["shapes"]), len(data["shapes"]), mine))
        elif want == "light":
            bt.check(len(data["lights"]) == len(base["lights"]) + 1 and not mine,
                     "%s: converted to a light, no line: %s" % (t, mine))
        elif want is None:
            bt.check(not mine and len(data["shapes"]) == len(base["shapes"]),
                     "%s: nothing to render (Cycles renders nothing of it either, or Blender "
                     "draws it), no line: %s" % (t, mine))
        else:
            bt.check(any(want in p for p in mine), "%s: reported by name ('%s'): %s"
                     % (t, want, mine))
            if t in ('CURVES', 'VOLUME'):  # the view layer's filter off: Cycles skips it too
                vl = bpy.context.view_layer
                setattr(vl, "use_strand" if t == 'CURVES' else "use_volumes", False)
                _, problems = export()
                bt.check(not [p for p in problems if "'Typed'" in p],
                         "%s: not reported with the view layer's filter off" % t)
    # The exporter's generic line for a type gaps.OBJECT_TYPES does not know.
    bt.check("FUTURE" in gaps.UNKNOWN_TYPE % "FUTURE", "the generic line names the type")


def case_components():
    """Geometry nodes turning the cube into points (the component is named) or a volume
    (converted)."""
    fresh()
    cube = bpy.data.objects["Cube"]
    ng = bpy.data.node_groups.new("gn", 'GeometryNodeTree')
    ng.inputs.new('NodeSocketGeometry', 'Geometry')
    ng.outputs.new('NodeSocketGeometry', 'Geometry')
    gi, go = ng.nodes.new('NodeGroupInput'), ng.nodes.new('NodeGroupOutput')
    cube.modifiers.new("gn", 'NODES').node_group = ng
    for kind, want in (('GeometryNodeMeshToPoints', "a pointcloud component"),
                       ('GeometryNodeMeshToVolume', None)):
        for n in [n for n in ng.nodes if n not in (gi, go)]:
            ng.nodes.remove(n)
        n = ng.nodes.new(kind)
        ng.links.new(gi.outputs[0], n.inputs[0])
        ng.links.new(n.outputs[0], go.inputs[0])
        data, problems = export()
        if want is None:
            # A volume component is converted as a VOLUME object (sync_volume.py); it has no
            # material (the mesh's are not the component's): Cycles' default volume shader.
            lines = [p for p in problems if p.startswith("object 'Cube'")]
            m = data.get("media", {}).get("Cube (volume)", {})
            bt.check(not lines and m.get("kind") == "grid" and m.get("grid") == "density",
                     "%s: the volume component is converted, no line: %s %s"
                     % (kind, lines, m))
            continue
        lines = [p for p in problems if p.startswith("object 'Cube'") and "component" in p]
        want = want.replace("pointcloud", "point cloud")
        bt.check(len(lines) == 1 and want in lines[0] and "not in Facet's core" in lines[0],
                 "%s: the component is reported: %s" % (kind, lines))


def _mesh():
    me = bpy.data.meshes.new("x")
    me.from_pydata([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [], [(0, 1, 2)])
    return me


def _point_lamp():
    lt = bpy.data.lights.new("x", 'POINT')
    lt.shadow_soft_size = 0.0  # a radius has its own line (gaps.LIGHTS)
    return lt


def _curve():
    cu = bpy.data.curves.new("x", 'CURVE')
    cu.dimensions = '3D'
    sp = cu.splines.new('POLY')
    sp.points.add(1)
    sp.points[0].co = (0, 0, 0, 1)
    sp.points[1].co = (1, 0, 0, 1)
    cu.bevel_depth = 0.1
    return cu


def _op(call):
    call()
    return bpy.context.active_object


def case_particle_hair():
    """Particle hair is converted (sync_hair.py: tests/blender/test_cycles_hair.py renders it
    against Cycles): a curves shape with a strand per hair, what it cannot convert reported."""
    fresh()
    cube = bpy.data.objects["Cube"]
    mod = cube.modifiers.new("Fur", 'PARTICLE_SYSTEM')
    st = mod.particle_system.settings
    st.type = 'HAIR'
    st.count = 50
    data, problems = export()
    hair = [s for s in data["shapes"] if s["type"] == "curves"]
    bt.check(len(hair) == 1 and len(hair[0]["counts"]) == 50,
             "particle hair converted: one curves shape of 50 strands")
    lines = [p for p in problems if "object 'Cube'" in p and "particle system" in p]
    # The factory hair's Close Tip (radius 0 at the tips) is the one thing approximated.
    bt.check(len(lines) == 1 and "radius 0 (Close Tip" in lines[0],
             "only Close Tip's zero radius reported: %s" % lines)
    mod.show_render = False
    data, problems = export()
    bt.check(not [p for p in problems if "particle system" in p] and
             not [s for s in data["shapes"] if s["type"] == "curves"],
             "a particle system hidden from renders: no hair, no line")
    mod.show_render = True
    bpy.context.view_layer.use_strand = False
    data, problems = export()
    bt.check(not [p for p in problems if "particle system" in p] and
             not [s for s in data["shapes"] if s["type"] == "curves"],
             "no hair and no line with the view layer's Curves filter off (Cycles renders none)")


def case_volume_material():
    """A Volume output alone is a medium behind a `null` surface (tests/blender/
    test_cycles_volume.py renders it against Cycles), never 'nothing connected'."""
    fresh()
    mat, nt, out = bt.new_material("Fog")
    vol = nt.nodes.new("ShaderNodeVolumePrincipled")
    nt.links.new(vol.outputs[0], out.inputs["Volume"])
    bpy.data.objects["Cube"].data.materials.clear()
    bpy.data.objects["Cube"].data.materials.append(mat)
    data, problems = export()
    lines = [p for p in problems if "material 'Fog'" in p]
    bt.check(not lines, "a Volume output alone converts, no line: %s" % lines)
    fog = dict(data["materials"])["Fog"]
    bt.check(fog == {"model": "null", "interior": "Fog"} and "Fog" in data.get("media", {}),
             "its surface is the null boundary of the medium 'Fog': %s" % fog)
    # Density 0: nothing inside, the surface is transparent (opacity 0, as Cycles renders
    # it). Rendered, the cube lets everything through: the image of the scene without it
    # (opacity 0 is exact: every candidate hit is skipped, camera and shadow rays alike; the
    # samples are the same, so the images agree to float rounding).
    vol.inputs["Density"].default_value = 0.0
    data, problems = export()
    fog = dict(data["materials"])["Fog"]
    bt.check(fog.get("opacity") == 0.0 and "media" not in data,
             "density 0: a transparent surface, no medium: %s" % fog)
    with_fog, _ = bt.render()
    bpy.data.objects["Cube"].hide_render = True
    without, _ = bt.render()
    bpy.data.objects["Cube"].hide_render = False
    diff = float(abs(with_fog - without).max())
    bt.check(diff <= 1e-5 * max(1.0, float(without.max())),
             "the empty volume cube renders as no cube: max difference %.3g" % diff)
    # Nothing on either: the old line stays.
    nt.links.remove(nt.links[0])
    _, problems = export()
    bt.check(any("material 'Fog': nothing connected to the output's Surface" in p
                 for p in problems), "an empty output still says so: %s" % problems)


def case_settings():
    """The render, Cycles, view layer and world settings: each walked property is classified
    by gaps.py; reported ones give a line when set away from Blender's factory value (and none
    at it); converted ones change the export."""
    from facet_blender import gaps
    scene = fresh()
    paths = {}
    for prefix, struct in roots(scene).items():
        for ident, prop in walked(struct):
            paths[prefix + "." + ident] = prop
    check_classified(sorted(paths))
    _, factory_lines = export()
    labels = [r[1] for t in (gaps.SETTINGS, gaps.OBJECT_FLAGS, gaps.LAMP_FLAGS,
                             gaps.COLLECTION_FLAGS) for r in t]
    ours = [p for p in factory_lines if any(la in p for la in labels)]
    bt.check(not ours, "Blender's factory scene gives no settings or flags line: %s"
             % factory_lines)
    n_rep = n_conv = 0
    for path, prop in sorted(paths.items()):
        kinds = dict(gaps.classify(path))
        if "reported" in kinds:
            row = reported_row(gaps.SETTINGS, path)
            scene = fresh()
            for p, pv in PREREQ.get(path, {}).items():
                setattr(*resolve(p), pv)
            struct, attr = resolve(path)
            v = away(struct, attr, prop, row[2], scene)
            bt.check(v is not None, "%s: a value away from the quiet ones" % path)
            setattr(struct, attr, v)
            _, problems = export()
            lines = [p for p in problems if row[1] in p]
            bt.check(len(lines) == 1, "%s = %r: reported as '%s': %s" % (path, v, row[1], lines))
            n_rep += 1
        elif "converted" in kinds:
            scene = fresh()
            for p, pv in PREREQ.get(path, {}).items():
                setattr(*resolve(p), pv)
            before, lines0 = fingerprint()
            struct, attr = resolve(path)
            v = away(struct, attr, prop)
            setattr(struct, attr, v)
            after, lines1 = fingerprint()
            bt.check(after != before or len(lines1) > len(lines0),
                     "%s = %r: converted (the export or its report changes)" % (path, v))
            n_conv += 1
    bt.check(n_rep == len(gaps.SETTINGS), "every SETTINGS row was walked (%d of %d)"
             % (n_rep, len(gaps.SETTINGS)))
    # Motion Blur with the view layer's Motion Blur filter off: Cycles renders it sharp too.
    scene = fresh()
    scene.render.use_motion_blur = True
    bpy.context.view_layer.use_motion_blur = False
    _, problems = export()
    bt.check(not [p for p in problems if "Motion Blur" in p],
             "no Motion Blur line with the view layer's filter off: %s" % problems)
    print("settings: %d walked, %d reported, %d converted" % (len(paths), n_rep, n_conv))


def case_object_flags():
    """The visibility flags and Cycles settings of a mesh object, a lamp and a collection."""
    from facet_blender import gaps
    fresh()
    cube = bpy.data.objects["Cube"]
    flag_props = [(i, p) for i, p in walked(cube)
                  if i.startswith(("visible_", "is_holdout", "is_shadow_catcher", "hide_render"))]
    bt.check(len(flag_props) >= 8, "the object's visibility flags: %s"
             % [i for i, _ in flag_props])
    cases = [("object." + i, p, lambda: bpy.data.objects["Cube"], "object 'Cube'", ".%s" % i)
             for i, p in flag_props]
    cases += [("object.cycles." + i, p, lambda: bpy.data.objects["Cube"], "object 'Cube'",
               "cycles.%s" % i) for i, p in walked(cube.cycles)]
    cases += [("lamp." + i, p, lambda: bpy.data.objects["Light"], "light 'Light'", i)
              for i, p in walked(bpy.data.objects["Light"])
              if i.startswith(("visible_", "is_holdout", "is_shadow_catcher"))]
    coll = bpy.data.collections["Collection"]
    lc = bpy.context.view_layer.layer_collection.children[coll.name]
    cases += [("collection." + i, p, lambda: bpy.context.view_layer.layer_collection.children[
        "Collection"], "collection 'Collection'", i) for i, p in walked(lc)]
    check_classified(sorted(c[0] for c in cases))
    tables = {"object.": gaps.OBJECT_FLAGS, "lamp.": gaps.LAMP_FLAGS,
              "collection.": gaps.COLLECTION_FLAGS}
    n_rep = 0
    for path, prop, owner, subject, _ in cases:
        kinds = dict(gaps.classify(path))
        prefix = path.split(".", 1)[0] + "."
        rel = path[len(prefix):]
        if "reported" in kinds:
            row = reported_row(tables[prefix], rel)
            fresh()
            target = owner()
            struct, attr = (target.cycles, rel.split(".")[1]) if rel.startswith("cycles.") \
                else (target, rel)
            quiet_owner = bpy.data.objects["Light"] if prefix == "lamp." else None
            v = away(struct, attr, prop, row[2], quiet_owner)
            setattr(struct, attr, v)
            _, problems = export()
            lines = [p for p in problems if p.startswith(subject) and row[1] in p]
            bt.check(len(lines) == 1, "%s = %r: reported for %s as '%s': %s"
                     % (path, v, subject, row[1], lines))
            n_rep += 1
        if "converted" in kinds:
            fresh()
            if path == "lamp.visible_camera":
                bpy.data.objects["Light"].data.type = 'AREA'
            if path == "object.hide_render":  # the render depsgraph's: an F12 render
                before = bt.render()[0]
                bpy.data.objects["Cube"].hide_render = True
                after = bt.render()[0]
                bt.check(before is not None and after is not None
                         and abs(float(before.mean()) - float(after.mean())) > 1e-3,
                         "%s: converted (the cube leaves the render: mean %.4g -> %.4g)"
                         % (path, before.mean(), after.mean()))
                continue
            before, _ = fingerprint()
            target = owner()
            setattr(target, rel, not getattr(target, rel))
            after, _ = fingerprint()
            bt.check(after != before, "%s: converted (the export changes)" % path)
    bt.check(n_rep == len(gaps.OBJECT_FLAGS) + len(gaps.LAMP_FLAGS) + len(gaps.COLLECTION_FLAGS),
             "every flag row was walked (%d)" % n_rep)
    # Object > Visibility > Shadow Catcher: the cube's shapes carry the flag, and no line.
    fresh()
    bpy.data.objects["Cube"].is_shadow_catcher = True
    data, problems = export()
    flags = [s.get("shadow_catcher", False) for s in data["shapes"]]
    bt.check(flags and all(flags) and not [p for p in problems if "Shadow Catcher" in p],
             "a shadow catcher is converted: the cube's shapes have shadow_catcher (%s), no "
             "report line (%s)" % (flags, problems))
    # Ray visibility is converted: an object only transmission and volume-scatter rays see is
    # exported with the other four flags off, and no line; one no ray sees is not exported.
    fresh()
    cube = bpy.data.objects["Cube"]
    for f in ("visible_camera", "visible_diffuse", "visible_glossy", "visible_shadow"):
        setattr(cube, f, False)
    data, problems = export()
    lines = [p for p in problems if p.startswith("object 'Cube'")]
    vis = [s.get("visibility") for s in data["shapes"]]
    want = {"camera": False, "diffuse": False, "glossy": False, "shadow": False}
    bt.check(vis == [want] and not lines,
             "an object only transmission rays see: exported with %s, no line: %s %s"
             % (want, vis, lines))
    cube.visible_transmission = cube.visible_volume_scatter = False
    data, problems = export()
    bt.check(not data["shapes"] and not [p for p in problems if p.startswith("object 'Cube'")],
             "an object no ray sees: not exported, no line")


def case_camera_clip():
    """The scene camera's Clip Start / Clip End (planes along the view axis, as Cycles clips):
    reported when they cut the cube off. The factory camera looks at the origin (11.26 away)
    along about (-0.654, 0.615, -0.440), so the cube's (+-1) corners lie at depths 11.26 -+
    1.71: 9.55 to 12.97."""
    fresh()
    cam = bpy.data.objects["Camera"].data

    def clip_lines():
        return [p for p in export()[1] if p.startswith("camera 'Camera'")]
    bt.check(not clip_lines(), "the factory clipping (0.1, 100) gives no line")
    for start, end, want in ((0.1, 13.5, None), (0.1, 12.5, "Clip End = 12.5"),
                             (9.4, 100.0, None), (9.7, 100.0, "Clip Start = 9.7")):
        cam.clip_start, cam.clip_end = start, end
        lines = clip_lines()
        if want is None:
            bt.check(not lines, "clip %g..%g cuts nothing off: no line: %s" % (start, end, lines))
        else:
            bt.check(len(lines) == 1 and want in lines[0] and "object 'Cube'" in lines[0],
                     "clip %g..%g cuts the cube: '%s': %s" % (start, end, want, lines))
    # A text object (its box from the exported vertices, not bound_box) 40 further along the
    # view axis: cut off by Clip End 30, which leaves the cube whole.
    fwd = -bpy.data.objects["Camera"].matrix_world.col[2].xyz.normalized()
    _op(lambda: bpy.ops.object.text_add(location=tuple(40.0 * fwd)))
    bpy.context.active_object.name = "Far"
    cam.clip_start, cam.clip_end = 0.1, 30.0
    lines = clip_lines()
    bt.check(len(lines) == 1 and "object 'Far'" in lines[0], "a far text object: %s" % lines)
    bpy.data.objects.remove(bpy.data.objects["Far"])
    cam.type = 'ORTHO'  # the same planes
    cam.clip_start, cam.clip_end = 0.1, 12.9
    lines = clip_lines()
    bt.check(len(lines) == 1 and "Clip End = 12.9" in lines[0], "orthographic: %s" % lines)
    cam.clip_end = 13.0
    bt.check(not clip_lines(), "orthographic, the cube within 13: no line: %s" % clip_lines())


def main():
    bt.enable_addon()
    for case in (case_object_types, case_particle_hair, case_volume_material, case_settings,
                 case_object_flags, case_camera_clip, case_components):
        print("--", case.__name__)
        case()


bt.run(main)
