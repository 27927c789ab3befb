"""What the motion-blur tests in Blender share (tests/blender/test_cycles_motion*.py,
test_cycles_hair_motion.py): the export with a frame setter, linear keyframes, Cycles' motion
blur settings of the comparisons, and the grey floor."""
import bpy


def export(frame_set=None):
    """export.export_scene of the current depsgraph; `frame_set` evaluates other times."""
    from facet_blender import export as ex
    return ex.export_scene(bpy.context.evaluated_depsgraph_get(), mesh_cache={},
                           frame_set=frame_set)


def scene_frame_set(frame, subframe):
    bpy.context.scene.frame_set(frame, subframe=subframe)


def linear(obj):
    """Every keyframe of `obj` interpolated linearly (constant speed over the shutter)."""
    for fc in obj.animation_data.action.fcurves:
        for kp in fc.keyframe_points:
            kp.interpolation = 'LINEAR'


def blur_on(scene):
    """Frame 1, motion blur on with shutter 0.5 centred on it."""
    scene.frame_set(1)
    scene.render.use_motion_blur = True
    scene.render.motion_blur_shutter = 0.5
    scene.cycles.motion_blur_position = 'CENTER'


def grey_floor(z, name="FloorMat"):
    """A 20-unit plane at height z with a Diffuse BSDF of 0.5."""
    from facet_testsupport import blender_harness as bt
    bpy.ops.mesh.primitive_plane_add(size=20.0, location=(0.0, 0.0, z))
    floor = bpy.context.active_object
    mat, nt, out = bt.new_material(name)
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (0.5, 0.5, 0.5, 1)
    nt.links.new(d.outputs[0], out.inputs["Surface"])
    floor.data.materials.append(mat)
    return floor
