"""Cycles node twins of an imported Facet JSON scene (used by blender_worker.py).

build(scene, data) gives every imported object whose Facet shape emits an Emission shader and
every Facet material a Cycles node tree, and the world the environment light; it returns a list
of notes (approximations made). Lambert -> Diffuse BSDF (roughness 0) is exact; emission ->
Emission (strength 1; Cycles' mesh lights emit from both sides, Facet's from the front only).
Other models are refused (a RuntimeError naming the material): a benchmark against a different
material would measure nothing."""
import json

import bpy


def _single(mat, idname, inputs):
    mat.use_nodes = True
    nt = mat.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    node = nt.nodes.new(idname)
    for k, v in inputs.items():
        node.inputs[k].default_value = v
    nt.links.new(node.outputs[0], out.inputs["Surface"])
    return node


def _rgb(v):
    v = [v] * 3 if isinstance(v, (int, float)) else list(v)
    return (v[0], v[1], v[2], 1.0)


def build(scene, data):
    notes = []
    for mat in list(bpy.data.materials):
        if "facet_material" not in mat:
            continue
        m = json.loads(mat["facet_material"])
        if m["model"] != "lambert":
            raise RuntimeError("%s: model %s has no Cycles twin here" % (mat.name, m["model"]))
        _single(mat, "ShaderNodeBsdfDiffuse",
                {"Color": _rgb(m.get("reflectance", 0.5)), "Roughness": 0.0})
    for ob in bpy.data.objects:
        if "facet_shape" not in ob:
            continue
        s = json.loads(ob["facet_shape"])
        em = s.get("emission")
        if em and any(_rgb(em)[:3]):
            mat = bpy.data.materials.new("%s (Cycles emission)" % ob.name)
            _single(mat, "ShaderNodeEmission", {"Color": _rgb(em), "Strength": 1.0})
            ob.data.materials.clear()
            ob.data.materials.append(mat)
            notes.append("%s: Cycles' mesh light emits from both sides" % ob.name)
    for lt in data.get("lights", []):
        if lt["type"] == "environment":
            world = scene.world
            world.use_nodes = True
            bg = world.node_tree.nodes["Background"]
            bg.inputs["Color"].default_value = _rgb(lt["radiance"])
            bg.inputs["Strength"].default_value = 1.0
    return notes
