"""Panels: Facet's render settings, the Facet material panel (the core's models and parameters
by the core's names), and Facet added to the COMPAT_ENGINES of Blender's usual panels (as
Cycles does), so camera, light, world, object and output panels stay visible."""
import bpy

from . import materials, plot, properties

_plot = []  # the PanelPlot while registered

ENGINE = 'FACET'

# Built-in panels that list BLENDER_RENDER but make no sense for Facet (Eevee/Workbench only).
_EXCLUDE = {
    'DATA_PT_light',  # Facet draws its own light panel below (Eevee's has Eevee-only options)
    'RENDER_PT_eevee_ambient_occlusion', 'RENDER_PT_eevee_motion_blur',
    'RENDER_PT_eevee_next_motion_blur', 'RENDER_PT_motion_blur_curve',
    'RENDER_PT_eevee_depth_of_field', 'RENDER_PT_eevee_bloom', 'RENDER_PT_eevee_volumetric',
    'RENDER_PT_eevee_volumetric_lighting', 'RENDER_PT_eevee_volumetric_shadows',
    'RENDER_PT_eevee_subsurface_scattering', 'RENDER_PT_eevee_screen_space_reflections',
    'RENDER_PT_eevee_shadows', 'RENDER_PT_eevee_sampling', 'RENDER_PT_eevee_indirect_lighting',
    'RENDER_PT_eevee_indirect_lighting_display', 'RENDER_PT_eevee_film',
    'RENDER_PT_eevee_hair', 'RENDER_PT_eevee_performance', 'DATA_PT_EEVEE_light',
    'DATA_PT_EEVEE_shadow', 'DATA_PT_EEVEE_shadow_cascaded_shadow_map',
    'DATA_PT_EEVEE_shadow_contact', 'DATA_PT_EEVEE_light_distance',
    'DATA_PT_lightprobe', 'DATA_PT_lightprobe_visibility', 'DATA_PT_lightprobe_parallax',
    'DATA_PT_lightprobe_display', 'MATERIAL_PT_viewport', 'EEVEE_MATERIAL_PT_context_material',
    'EEVEE_MATERIAL_PT_surface', 'EEVEE_MATERIAL_PT_volume', 'EEVEE_MATERIAL_PT_settings',
    'EEVEE_WORLD_PT_surface', 'EEVEE_WORLD_PT_volume', 'EEVEE_WORLD_PT_mist',
    'VIEWLAYER_PT_eevee_layer_passes_data', 'VIEWLAYER_PT_eevee_layer_passes_light',
    'VIEWLAYER_PT_eevee_layer_passes_effects', 'RENDER_PT_simplify_greasepencil',
}
# Cycles' material panels cannot be shared: their polls test Cycles' mixin's COMPAT_ENGINES
# (one set for every Cycles panel), so Facet draws its own slot list, preview and node panels
# below (the same templates Cycles' ui.py uses).
_CYCLES_PANELS = ()


def _compat_panels():
    out = []
    for panel in bpy.types.Panel.__subclasses__():
        ce = getattr(panel, 'COMPAT_ENGINES', None)
        if ce is None:
            continue
        name = panel.__name__
        if ('BLENDER_RENDER' in ce and name not in _EXCLUDE) or name in _CYCLES_PANELS:
            out.append(panel)
    return out


class FacetPanel:
    bl_space_type = 'PROPERTIES'
    bl_region_type = 'WINDOW'
    COMPAT_ENGINES = {ENGINE}
    needs = None  # a context member that must be set ("material", "light", ...)

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES and (
            cls.needs is None or getattr(context, cls.needs, None) is not None)


class FacetMaterialPanel(FacetPanel):
    bl_context = "material"
    needs = "material"


class FACET_PT_render(FacetPanel, bpy.types.Panel):
    bl_label = "Facet"
    bl_context = "render"

    def draw(self, context):
        fs = context.scene.facet
        lay = self.layout
        lay.use_property_split = True
        lay.prop(fs, "integrator")
        lay.prop(fs, "spp")
        lay.prop(fs, "viewport_spp")
        sub = lay.row()
        sub.active = not fs.viewport_denoise
        sub.prop(fs, "viewport_adaptive_threshold")
        lay.prop(fs, "time_budget")
        col = lay.column(align=True)
        col.prop(fs, "adaptive_threshold")
        sub = col.row()
        sub.active = fs.adaptive_threshold > 0.0
        sub.prop(fs, "adaptive_min_samples")
        lay.prop(fs, "max_depth")
        lay.prop(fs, "light_selection")
        lay.prop(fs, "lamp_model")
        lay.prop(fs, "denoise")
        lay.prop(fs, "viewport_denoise")
        row = lay.row(align=True)
        row.prop(fs, "seed")
        row.prop(fs, "animated_seed", text="", icon='TIME')
        rd = context.scene.render
        lay.prop(rd, "threads_mode")
        sub = lay.row()
        sub.enabled = rd.threads_mode == 'FIXED'
        sub.prop(rd, "threads")
        lay.prop(fs, "bake")
        sub = lay.column()
        sub.enabled = fs.bake
        sub.prop(fs, "bake_resolution")
        sub.operator("facet.bake_inputs", icon='RENDER_STILL')


class FACET_PT_passes(FacetPanel, bpy.types.Panel):
    bl_label = "Passes"
    bl_context = "view_layer"

    def draw(self, context):
        vl = context.view_layer
        col = self.layout.column(heading="Include")
        col.use_property_split = True
        col.prop(vl, "use_pass_combined")
        col.prop(vl, "use_pass_z")
        col.prop(vl, "use_pass_normal")
        col.prop(vl, "use_pass_emit", text="Emission")
        col.prop(vl.facet, "use_pass_albedo")
        if hasattr(vl, "cycles"):  # Cycles' toggle (its addon is on in a default Blender)
            col.prop(vl.cycles, "denoising_store_passes", text="Denoising Data")
            col.prop(vl.cycles, "use_pass_shadow_catcher", text="Shadow Catcher")


class FACET_PT_context_material(FacetPanel, bpy.types.Panel):
    bl_label = ""
    bl_context = "material"
    bl_options = {'HIDE_HEADER'}

    @classmethod
    def poll(cls, context):
        ob = context.active_object
        return (super().poll(context) and (context.material or context.object) is not None
                and not (ob and ob.type == 'GPENCIL'))

    def draw(self, context):
        lay = self.layout
        ob, mat, slot = context.object, context.material, context.material_slot
        space = context.space_data
        if ob:
            is_sortable = len(ob.material_slots) > 1
            row = lay.row()
            row.template_list("MATERIAL_UL_matslots", "", ob, "material_slots", ob,
                              "active_material_index", rows=3 if is_sortable else 1)
            col = row.column(align=True)
            col.operator("object.material_slot_add", icon='ADD', text="")
            col.operator("object.material_slot_remove", icon='REMOVE', text="")
        split = lay.split(factor=0.65)
        if ob:
            split.template_ID(ob, "active_material", new="material.new")
            row = split.row()
            if slot:
                row.prop(slot, "link", text="")
        elif mat:
            split.template_ID(space, "pin_id")


class FACET_PT_material_preview(FacetMaterialPanel, bpy.types.Panel):
    bl_label = "Preview"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        self.layout.template_preview(context.material)


def _node_panel(layout, id_data, output_type, input_name, fallback):
    if not id_data.use_nodes:
        layout.prop(id_data, "use_nodes", icon='NODETREE')
        layout.prop(id_data, fallback)
        return
    ntree = id_data.node_tree
    node = ntree.get_output_node('CYCLES')
    if node is None:
        layout.label(text="No output node")
        return
    sock = next((i for i in node.inputs if i.name == input_name), None)
    if sock is not None:
        layout.template_node_view(ntree, node, sock)


class FACET_PT_material_surface(FacetMaterialPanel, bpy.types.Panel):
    bl_label = "Surface"

    def draw(self, context):
        _node_panel(self.layout, context.material, 'OUTPUT_MATERIAL', 'Surface',
                    "diffuse_color")


class FACET_PT_world_surface(FacetPanel, bpy.types.Panel):
    bl_label = "Surface"
    bl_context = "world"
    needs = "world"

    def draw(self, context):
        _node_panel(self.layout, context.world, 'OUTPUT_WORLD', 'Surface', "color")


class FACET_PT_material(FacetMaterialPanel, bpy.types.Panel):
    bl_label = "Facet Material"

    def draw(self, context):
        mat = context.material
        ms = mat.facet
        lay = self.layout
        if _plot:
            conv = materials.convert(mat)
            icon, err = _plot[0].icon(mat.name, conv.data)
            lay.template_icon(icon_value=icon, scale=10.0)
            lay.label(text="%s: lobe at 45 deg (top), albedo vs angle (bottom)"
                      % conv.data["model"])
            if err:
                lay.label(text=err, icon='ERROR')
            for p in conv.problems[:3]:
                lay.label(text=p, icon='INFO')
        lay.use_property_split = True
        lay.prop(ms, "source")
        lay.prop(ms, "two_sided")
        if ms.source != 'FACET':
            lay.label(text="Converts Diffuse, Glossy, Anisotropic, Principled BSDF, Emission")
            return
        lay.prop(ms, "model")
        lay.prop(ms, "emission")
        model = next((m for m in properties.MODELS if m["name"] == ms.model), None)
        if model is None:
            return
        lay.label(text=model["summary"])
        for p in model["params"]:
            name = properties.prop_name(model["name"], p["name"])
            row = lay.row(heading=p["name"])
            row.prop(ms, name + "__set", text="")
            sub = row.row()
            sub.active = getattr(ms, name + "__set")
            sub.prop(ms, name, text="")


class FACET_PT_light(FacetPanel, bpy.types.Panel):
    bl_label = "Light"
    bl_context = "data"
    needs = "light"

    def draw(self, context):
        lt = context.light
        lay = self.layout
        lay.row().prop(lt, "type", expand=True)
        lay.use_property_split = True
        lay.prop(lt, "color")
        lay.prop(lt, "energy")
        if lt.type == 'SPOT':
            lay.prop(lt, "spot_size")
            lay.prop(lt, "spot_blend")
        elif lt.type == 'AREA':
            lay.prop(lt, "shape")
            lay.prop(lt, "size")
            if lt.shape in ('RECTANGLE', 'ELLIPSE'):
                lay.prop(lt, "size_y")
        lay.label(text="Cycles' units; radius, angle and spread are not used by Facet")


class FACET_PT_object(FacetPanel, bpy.types.Panel):
    bl_label = "Facet Shape"
    bl_context = "object"

    @classmethod
    def poll(cls, context):
        return (super().poll(context) and context.object is not None
                and "facet_shape" in context.object)

    def draw(self, context):
        import json
        ob = context.object
        shape = json.loads(ob["facet_shape"])
        self.layout.label(text="Exact Facet %s (imported); the mesh is for display" %
                          shape["type"])
        self.layout.operator("facet.clear_shape")


_panels = []  # (panel class, its own COMPAT_ENGINES before, or None when inherited)
_classes = (FACET_PT_render, FACET_PT_passes, FACET_PT_context_material,
            FACET_PT_material_preview, FACET_PT_material_surface, FACET_PT_material,
            FACET_PT_world_surface, FACET_PT_light, FACET_PT_object)


def register():
    for c in _classes:
        bpy.utils.register_class(c)
    _plot[:] = [plot.PanelPlot()]
    # Each panel gets its own set: COMPAT_ENGINES is often a set shared through a mixin (all of
    # Cycles' panels share CyclesButtonsPanel's), and adding to it in place would show every
    # panel of the mixin.
    _panels.clear()
    for p in _compat_panels():
        own = p.__dict__.get("COMPAT_ENGINES")
        _panels.append((p, own))
        p.COMPAT_ENGINES = set(p.COMPAT_ENGINES) | {ENGINE}


def unregister():
    for p, own in _panels:
        if own is None:
            del p.COMPAT_ENGINES
        else:
            p.COMPAT_ENGINES = own
    _panels.clear()
    for p in _plot:
        p.close()
    _plot.clear()
    for c in reversed(_classes):
        bpy.utils.unregister_class(c)
