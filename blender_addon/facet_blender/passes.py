"""Render passes besides Combined, for Blender's compositor: Depth, Normal, Emit (Blender's
own View Layer toggles Z, Normal and Emission) and Albedo (the view layer's Facet toggle),
computed by the core's first-hit pass (facet/render/aov.h) after the beauty render, only
when enabled (nothing is computed otherwise):

- Depth ("Z"): distance from the camera along its view axis, as Cycles 3.4's Z pass
  (camera_z_depth: the camera-space z of the hit), 1e10 where nothing is hit; Facet averages
  the samples that hit, Cycles averages all samples with 0 for misses and writes 1e10 only
  where every sample missed (silhouette pixels differ). As Cycles, from the render's own camera
  samples (the session sums it while rendering: RenderOptions::depth_pass), unless the scene
  has motion blur or ray visibility or the render is denoised: then from the first-hit pass
  below, whose samples are the render's first min(spp, 64).
- Normal ("XYZ"): the world-space shading normal (after normal and bump maps) turned toward
  the viewer, averaged over the pixel's samples, 0 where nothing is hit (as Cycles).
- Emit ("RGB"): the radiance the surface seen emits toward the camera (not the world: that
  is Blender's Environment pass).
- Albedo ("RGB"): the material's directional albedo rho(wo) toward the viewer (reflection
  and transmission), a one-BSDF-sample estimate per camera sample (exact for Lambert).
  Cycles' nearest pass, Denoising Albedo, sums its closures' albedo estimates, which agrees
  for Lambert and differs for glossy lobes.
- Denoising Data (View Layer > Passes > Data > Denoising Data, Cycles' toggle
  denoising_store_passes, under Cycles' names): Denoising Normal, Denoising Albedo and
  Denoising Depth, the features the denoiser (Render Properties > Facet > Denoise) uses: the
  same values as Normal, Albedo and Depth above.
- Shadow Catcher (View Layer > Passes > Light > Shadow Catcher, Cycles' toggle
  use_pass_shadow_catcher, "RGB"): Cycles 3.4's pass, from the beauty render's own sums (the
  core's Film, scenes/FORMAT.md "Shadow catchers"): per channel the light the shadow catchers
  kept, 1 where none is seen. As in Cycles, turning it on changes the Combined pass of a scene
  with a catcher: the other objects alone, with their alpha (final.py asks the session for it).
"""
import numpy as np

from . import native

# (Blender pass name, core pass, channels, channel ids, type, ViewLayer toggle)
PASSES = (
    ("Depth", "depth", 1, "Z", 'VALUE', "use_pass_z"),
    ("Normal", "normal", 3, "XYZ", 'VECTOR', "use_pass_normal"),
    ("Emit", "emission", 3, "RGB", 'COLOR', "use_pass_emit"),
    ("Albedo", "albedo", 3, "RGB", 'COLOR', "facet.use_pass_albedo"),
    ("Denoising Normal", "normal", 3, "XYZ", 'VECTOR', "cycles.denoising_store_passes"),
    ("Denoising Albedo", "albedo", 3, "RGB", 'COLOR', "cycles.denoising_store_passes"),
    ("Denoising Depth", "depth", 1, "Z", 'VALUE', "cycles.denoising_store_passes"),
)


# The Shadow Catcher pass: (Blender pass name, channels, channel ids, type, ViewLayer toggle).
SHADOW_CATCHER = ("Shadow Catcher", 3, "RGB", 'COLOR', "cycles.use_pass_shadow_catcher")


def _enabled(view_layer, toggle):
    obj = view_layer
    for part in toggle.split(".")[:-1]:
        obj = getattr(obj, part, None)
        if obj is None:
            return False
    return bool(getattr(obj, toggle.split(".")[-1], False))


def enabled(view_layer):
    """The PASSES entries the view layer asks for."""
    return [p for p in PASSES if _enabled(view_layer, p[5])]


def shadow_catcher_pass(view_layer):
    """Whether the view layer asks for the Shadow Catcher pass."""
    return _enabled(view_layer, SHADOW_CATCHER[4])


def register_passes(engine, scene, view_layer):
    """RenderEngine.update_render_passes: Combined and the enabled passes."""
    engine.register_pass(scene, view_layer, "Combined", 4, "RGBA", 'COLOR')
    for name, _, n, chans, ptype, _ in enabled(view_layer):
        engine.register_pass(scene, view_layer, name, n, chans, ptype)
    if shadow_catcher_pass(view_layer):
        engine.register_pass(scene, view_layer, *SHADOW_CATCHER[:4])


def write_shadow_catcher(result, image):
    """Writes the Shadow Catcher pass (float32 (h, w, 3), the core's top-down image of the
    render's region) into the render result."""
    flat = np.ascontiguousarray(image[::-1, :, :3], dtype=np.float32).reshape(-1, 3)
    result.layers[0].passes[SHADOW_CATCHER[0]].rect.foreach_set(flat)


def wants_depth(view_layer):
    """Whether the view layer asks for a pass of the core's depth (Depth, Denoising Depth)."""
    return any(p[1] == "depth" for p in enabled(view_layer))


def write(result, fscene, view_layer, spp, seed, threads, crop, depth=None):
    """Computes the enabled passes over the whole image and writes the `crop` (x0, y0, x1, y1
    of the core's top-down image; the border) into the render result's passes; `depth`, the
    render session's Depth pass of the crop (float32 (h, w), native.Session.depth()), when it
    has one. Returns the names written."""
    want = [p for p in enabled(view_layer)]
    if not want:
        return []
    cores = sorted({p[1] for p in want} - ({"depth"} if depth is not None else set()))
    imgs = native.render_aovs(fscene, cores, spp=spp, seed=seed, threads=threads) if cores else {}
    x0, y0, x1, y1 = crop
    layer = result.layers[0]
    for name, core, n, _, _, _ in want:
        if core == "depth" and depth is not None:
            img = depth[:, :, None]  # the crop's already
        else:
            img = imgs[core][y0:y1, x0:x1]
        flat = np.ascontiguousarray(img[::-1, :, :n], dtype=np.float32).reshape(-1, n)
        layer.passes[name].rect.foreach_set(flat)
    return [p[0] for p in want]
