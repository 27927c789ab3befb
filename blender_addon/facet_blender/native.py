"""The one place that talks to the native `facet` module (pybind11, core/python/).

The rest of the addon works on *scene data*: plain Python dicts and numpy arrays in the
vocabulary of scenes/FORMAT.md (keys and shape types as in the JSON format; mesh arrays as
numpy: positions float32 (n, 3), indices int32 (m, 3), normals float32 (n, 3) or None;
transforms as 4x4 row-major nested lists of floats acting on column vectors, or None).
to_description() turns it into a facet.SceneDescription and from_description() back, so the
binding's names appear only here.
"""
import json
import os
import sys

import numpy as np

_LIB_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "lib")


class NativeImportError(ImportError):
    pass


def _import_facet():
    if os.path.isdir(_LIB_DIR) and _LIB_DIR not in sys.path:
        sys.path.insert(0, _LIB_DIR)
    try:
        import facet  # noqa: F401  (the native module shipped in lib/ by the zip target)
    except ImportError as e:
        raise NativeImportError(
            "Facet: cannot import the native 'facet' module (%s). The addon zip built by the "
            "CMake target 'blender_addon_zip' ships it in facet_blender/lib/; it is built for "
            "Python %d.%d (Debian's /usr/bin/python3, which Debian's Blender 3.4.1 embeds) and "
            "links the system Embree 3 and TBB; this Blender runs Python %d.%d."
            % (e, 3, 11, sys.version_info[0], sys.version_info[1])) from e
    return facet


facet = _import_facet()


def curve_random(indices):
    """Cycles 3.4's random values (float64 array) of the strands of these indices in a hair
    geometry: what a curves shape without strand_random gives strand i (scene.h)."""
    return np.asarray(facet.curve_random(np.asarray(indices, np.int64)), np.float64)


# --- model table ---------------------------------------------------------------------------

def models():
    """The core's model table as [{'name', 'summary', 'params': [{'name', 'type', 'default',
    'doc'}]}], type one of 'number', 'colour', 'string', 'bool'; default the table's text."""
    out = []
    for m in facet.models():
        params = []
        for p in m.params:
            t = {"color": "colour"}.get(p.type, p.type)
            params.append({"name": p.name, "type": t, "default": p.default, "doc": p.doc})
        out.append({"name": m.name, "summary": m.summary, "params": params})
    return out


def check_material(model, params):
    """Validates a material with the core's registry; raises ValueError naming the parameter."""
    facet.make_material(model, **params)


# --- light units -------------------------------------------------------------------------
# The core's conversions (light_units.h) under their C++ names; units.py converts through them.

def point_intensity(power):
    """Intensity (W/sr, [r, g, b]) of an isotropic point light of power Phi: Phi / (4 pi)."""
    return list(facet.point_intensity(power))


def spot_intensity(power, inner_deg, outer_deg):
    """On-axis intensity I0 ([r, g, b]) of Facet's linear spot of power Phi (FORMAT.md)."""
    return list(facet.spot_intensity(power, inner_deg, outer_deg))


def cycles_spot_intensity(power, outer_deg, blend):
    """K ([r, g, b]) of Facet's spot in Blender's form (Cycles 3.4's fall-off) of power Phi."""
    return list(facet.cycles_spot_intensity(power, outer_deg, blend))


def cycles_volume(density, color, absorption_color):
    """(sigma_a, sigma_s) ([r, g, b] each, per scene unit) of Cycles' Principled Volume
    (medium.h: cycles_volume)."""
    sa, ss = facet.cycles_volume(float(density), [float(c) for c in color],
                                 [float(c) for c in absorption_color])
    return [float(c) for c in sa], [float(c) for c in ss]


# --- scene data <-> SceneDescription --------------------------------------------------------

_SHAPE_KEYS = {
    "sphere": ("center", "radius"),
    "plane": ("point", "normal"),
    "disc": ("center", "normal", "radius"),
    "box": ("min", "max"),
    "quad": ("vertices",),
    "icosphere": ("center", "radius", "subdivisions", "smooth"),
    "grid": ("nx", "ny", "amplitude", "frequency"),
    "mesh": (),
    "instance": ("of",),
    "curves": ("basis", "profile"),
}
# Every light kind's keys, from the core's kind table (kinds.h): sizes, Blender's spot blend,
# the area lamp and environment maps travel with their lights.
_LIGHT_KEYS = {kind: tuple(keys) for kind, keys in facet.light_kind_keys().items()}


def texture(t):
    """A scene-format texture dict (FORMAT.md, Textures) -> facet.Texture."""
    if t.get("vertex_color"):
        return facet.Texture.vertex_color(t.get("channel", ""), float(t.get("scale", 1.0)))
    kind = next((k for k, v in t.items() if isinstance(v, dict) and k not in (
        "checker", "mapping")), None)
    if kind is not None:  # a procedural kind: {"noise": {params}, "coordinates", "mapping"}
        m = t.get("mapping")
        params = {}
        for k, v in t[kind].items():
            if isinstance(v, dict):  # a composite kind's input fed by a texture
                v = texture(v)
            elif k == "stops":  # a colour ramp's stops
                v = [(float(st["position"]), tuple(float(c) for c in st["color"])) for st in v]
            elif isinstance(v, (list, tuple)):  # a colour
                v = tuple(float(c) for c in v)
            params[k] = v
        return facet.Texture.procedural(kind, coordinates=t.get("coordinates", ""),
                                        mapping=m["matrix"] if m else None,
                                        value_scale=float(t.get("scale", 1.0)),
                                        channel=t.get("channel", ""), **params)
    uv = {"uv_scale": tuple(t.get("uv_scale", (1.0, 1.0))),
          "uv_offset": tuple(t.get("uv_offset", (0.0, 0.0))),
          "uv_rotation": float(t.get("uv_rotation", 0.0))}
    if "checker" in t:
        c = t["checker"]
        c0, c1 = (_rgb(x) for x in c["colors"])
        return facet.Texture.checker(c0, c1, scale=float(c.get("scale", 1.0)),
                                     value_scale=float(t.get("scale", 1.0)), **uv)
    return facet.Texture(t["texture"], colorspace=t.get("colorspace", ""),
                         filter=t.get("filter", ""), wrap=t.get("wrap", ""),
                         scale=float(t.get("scale", 1.0)), channel=t.get("channel", ""), **uv)


# The keys a material's normal_map / bump takes besides its texture's (FORMAT.md).
_MAP_KEYS = {"normal_map": ("strength", "xy_scale"), "bump": ("distance", "strength")}


def _material_desc(m):
    """A material dict -> facet.MaterialDesc: textures for texture dicts, the sub-materials of
    a mix / add (names or material dicts, nested), normal_map and bump."""
    params = {}
    for k, v in m.items():
        if k == "model":
            continue
        if k == "materials":
            v = [c if isinstance(c, str) else _material_desc(c) for c in v]
        elif k in _MAP_KEYS:
            v = dict({x: float(v[x]) for x in _MAP_KEYS[k] if x in v}, texture=texture(v))
        elif isinstance(v, dict):
            v = texture(v)
        params[k] = v
    return facet.MaterialDesc(m["model"], params)


def _rgb(v):
    if isinstance(v, (int, float)):
        return [float(v)] * 3
    return [float(c) for c in v]


def _shape_desc(s):
    sd = facet.ShapeDesc()
    if s["type"] == "instance":  # a placement: its prototype, name and transform only
        sd.kind = "instance"
        sd.of = s["of"]
        sd.name = s.get("name", "")
        if s.get("transform") is not None:
            sd.transform = np.asarray(s["transform"], dtype=np.float64)
        if s.get("motion"):
            sd.motion = [np.asarray(m, dtype=np.float64) for m in s["motion"]]
        return sd
    sd.kind = s["type"]
    sd.name = s.get("name", "")
    mat = s.get("material")
    if isinstance(mat, dict):
        sd.material = _material_desc(mat)
    elif mat:
        sd.material_ref = mat
    if isinstance(s.get("emission"), dict):
        sd.emission_texture = texture(s["emission"])
    elif "emission" in s:
        sd.emission = _rgb(s["emission"])
    sd.two_sided = bool(s.get("two_sided", True))
    sd.flip_normals = bool(s.get("flip_normals", False))
    sd.holdout = bool(s.get("holdout", False))
    sd.shadow_catcher = bool(s.get("shadow_catcher", False))
    if s.get("visibility"):  # FORMAT.md "Ray visibility"
        sd.visibility = {k: bool(v) for k, v in s["visibility"].items()}
    if s.get("light_path"):  # FORMAT.md "Light Path switches"
        sd.light_path = [dict(e, material=_material_desc(e["material"])
                              if isinstance(e.get("material"), dict) else e.get("material"),
                              emission=_rgb(e.get("emission", 0.0))) for e in s["light_path"]]
    if "texture_space" in s:
        ts = s["texture_space"]
        sd.texture_space = (_rgb(ts["location"]), _rgb(ts["size"]))
    if s.get("transform") is not None:
        sd.transform = np.asarray(s["transform"], dtype=np.float64)
    if s.get("motion"):
        sd.motion = [np.asarray(m, dtype=np.float64) for m in s["motion"]]
    for k in _SHAPE_KEYS[s["type"]]:
        if k in s:
            setattr(sd, k, s[k])
    if s["type"] == "curves":  # FORMAT.md "Curves": float32 / uint32 arrays
        radius = s["radius"]
        sd.curves = facet.CurveData(
            points=np.ascontiguousarray(s["points"], dtype=np.float32),
            radius=float(radius) if isinstance(radius, (int, float)) else
            np.ascontiguousarray(radius, dtype=np.float32),
            counts=None if s.get("counts") is None else np.asarray(s["counts"], np.int64),
            root_uvs=None if s.get("root_uvs") is None else
            np.ascontiguousarray(s["root_uvs"], dtype=np.float32),
            strand_random=None if s.get("strand_random") is None else
            np.ascontiguousarray(s["strand_random"], dtype=np.float32))
        if s.get("motion_positions"):  # deformation motion: per step, flat float32 arrays
            sd.motion_positions = [np.ascontiguousarray(st, dtype=np.float32).ravel()
                                   for st in s["motion_positions"]]
    if s["type"] == "mesh":
        if "file" in s:
            sd.file = s["file"]
        else:
            sd.mesh = facet.MeshData(*(
                None if s.get(k) is None else
                np.ascontiguousarray(s[k], dtype=np.int32 if k == "indices" else np.float32)
                for k in ("positions", "indices", "normals", "uvs", "tangents", "colors")))
        # Deformation motion (FORMAT.md "Motion blur"): per step, flat float32 arrays.
        for k in ("motion_positions", "motion_normals"):
            if s.get(k):
                setattr(sd, k, [np.ascontiguousarray(st, dtype=np.float32).ravel()
                                for st in s[k]])
    return sd


# The camera's optional keys (FORMAT.md "camera"), absent from scene data when at the default.
CAMERA_OPTIONAL = ("type", "scale", "shift_x", "shift_y", "aperture_radius", "fstop",
                   "focal_length", "focus_distance", "blades", "rotation")
_CAMERA_DEFAULTS = {"type": "perspective", "shift_x": 0.0, "shift_y": 0.0, "blades": 0,
                    "rotation": 0.0}


def to_description(data):
    """Scene data -> facet.SceneDescription (no validation here: build_scene validates)."""
    d = facet.SceneDescription()
    d.description = data.get("description", "")
    cam = data["camera"]
    c = d.camera
    c.position = list(cam["position"])
    c.look_at = list(cam["look_at"])
    c.up = list(cam["up"])
    if "fov" in cam:
        c.fov = float(cam["fov"])
    c.width = int(cam["width"])
    c.height = int(cam["height"])
    for key in CAMERA_OPTIONAL:
        if key in cam:
            setattr(c, key, cam[key])
    if cam.get("motion"):
        c.motion = [facet.CameraStep(position=list(st["position"]), look_at=list(st["look_at"]),
                                     up=list(st.get("up", cam["up"]))) for st in cam["motion"]]
    d.camera = c
    d.materials = {name: _material_desc(m) for name, m in data.get("materials", [])}
    shapes = []
    for i, s in enumerate(data.get("shapes", [])):
        try:
            shapes.append(_shape_desc(s))
        except (ValueError, TypeError) as e:  # bad arrays: name the shape as build_scene does
            raise ValueError("%s: /shapes/%d ('%s'): %s" % (data.get("name", "blender"), i,
                                                           s.get("name", ""), e)) from e
    d.shapes = shapes
    prototypes = {}
    for pname, pshapes in data.get("prototypes", {}).items():
        descs = []
        for i, s in enumerate(pshapes):
            try:
                descs.append(_shape_desc(s))
            except (ValueError, TypeError) as e:
                raise ValueError("%s: /prototypes/%s/%d ('%s'): %s"
                                 % (data.get("name", "blender"), pname, i, s.get("name", ""),
                                    e)) from e
        prototypes[pname] = descs
    if prototypes:
        d.prototypes = prototypes
    lights = []
    for lt in data.get("lights", []):
        ld = facet.LightDesc()
        ld.kind = lt["type"]
        for k in _LIGHT_KEYS[lt["type"]]:
            if k in lt and lt[k] is not None:
                setattr(ld, k, lt[k])
        lights.append(ld)
    d.lights = lights
    media = data.get("media") or {}
    if media:
        d.media = {name: _medium_desc(m) for name, m in media.items()}
    if data.get("world_medium"):
        d.world_medium = data["world_medium"]
    r = d.render
    rs = data.get("render", {})
    if "integrator" in rs:
        r.integrator = rs["integrator"]
    if "spp" in rs:
        r.spp = int(rs["spp"])
    if "time_budget" in rs:
        r.time_budget_s = float(rs["time_budget"])
    if "max_depth" in rs:
        r.max_depth = int(rs["max_depth"])
    if "seed" in rs:
        r.seed = int(rs["seed"])
    if "adaptive_threshold" in rs:
        r.adaptive_threshold = float(rs["adaptive_threshold"])
        r.adaptive_min_samples = int(rs.get("adaptive_min_samples", 0))
    if rs.get("film_transparent", False):
        r.film_transparent = True
    mb = rs.get("motion_blur")
    if mb is not None:
        r.motion_blur = facet.MotionBlur(enabled=mb) if isinstance(mb, bool) else \
            facet.MotionBlur(**{k: (list(v) if k == "curve" else v) for k, v in mb.items()})
    d.render = r
    return d


def _vec(v):
    return [float(x) for x in v]


def _params(p):
    out = {}
    for k, v in dict(p).items():
        out[k] = _vec(v) if isinstance(v, (list, tuple, np.ndarray)) else v
    return out


def _material_data(m):
    out = {"model": m.model}
    out.update(_params(m.params))
    if m.materials:
        out["materials"] = [c if isinstance(c, str) else _material_data(c) for c in m.materials]
    return out


def _shape_data(sd, base_dir):
    """facet.ShapeDesc -> a shape dict of the scene format."""
    kind = str(sd.kind).split(".")[-1].lower()
    s = {"type": kind, "name": sd.name, "two_sided": bool(sd.two_sided),
         "flip_normals": bool(sd.flip_normals), "emission": _vec(sd.emission)}
    if sd.holdout:
        s["holdout"] = True
    if sd.shadow_catcher:
        s["shadow_catcher"] = True
    off = {k: False for k, v in sd.visibility.items() if not v}
    if off:
        s["visibility"] = off
    if sd.light_path:
        s["light_path"] = [dict(e, material=_material_data(e["material"])
                                if isinstance(e["material"], facet.MaterialDesc)
                                else e["material"], emission=_vec(e["emission"]))
                           for e in sd.light_path]
        for e in s["light_path"]:
            if e["material"] is None:
                del e["material"]
    if sd.material is not None:
        s["material"] = _material_data(sd.material)
    elif sd.material_ref:
        s["material"] = sd.material_ref
    t = sd.transform
    s["transform"] = None if t is None else np.asarray(t, dtype=np.float64).tolist()
    if sd.motion:
        s["motion"] = [np.asarray(m, dtype=np.float64).tolist() for m in sd.motion]
    for k in _SHAPE_KEYS[kind]:
        v = getattr(sd, k)
        if k == "vertices":
            v = [_vec(p) for p in v]
        elif isinstance(v, (list, tuple, np.ndarray)):
            v = _vec(v)
        s[k] = v
    if kind == "curves":
        c = sd.curves
        s["points"] = np.asarray(c.points, dtype=np.float64).ravel().tolist()
        s["radius"] = c.radius if isinstance(c.radius, float) else \
            np.asarray(c.radius, dtype=np.float64).tolist()
        if c.counts is not None:
            s["counts"] = [int(x) for x in c.counts]
        if c.root_uvs is not None:
            s["root_uvs"] = np.asarray(c.root_uvs, dtype=np.float64).ravel().tolist()
        if c.strand_random is not None:
            s["strand_random"] = np.asarray(c.strand_random, dtype=np.float64).tolist()
        if len(sd.motion_positions):
            s["motion_positions"] = [np.asarray(st, dtype=np.float64).ravel().tolist()
                                     for st in sd.motion_positions]
    if kind == "mesh":
        if sd.file:
            s["file"] = os.path.join(base_dir, sd.file)
        else:
            mesh = sd.mesh
            s["positions"] = np.array(mesh.positions, dtype=np.float32).reshape(-1, 3)
            s["indices"] = np.array(mesh.indices, dtype=np.int32).reshape(-1, 3)
            n = mesh.normals
            s["normals"] = None if n is None or len(n) == 0 else np.array(
                n, dtype=np.float32).reshape(-1, 3)
        for k in ("motion_positions", "motion_normals"):
            steps = getattr(sd, k)
            if len(steps):
                s[k] = [np.asarray(st, dtype=np.float32).reshape(-1, 3) for st in steps]
    return s


def from_description(d):
    """facet.SceneDescription -> scene data (every field the format has)."""
    c = d.camera
    data = {
        "description": d.description,
        "camera": {"position": _vec(c.position), "look_at": _vec(c.look_at), "up": _vec(c.up),
                   "width": int(c.width), "height": int(c.height)},
        "materials": [(name, _material_data(m)) for name, m in d.materials.items()],
        "lights": [],
    }
    cam = data["camera"]
    if c.type == "perspective":
        cam["fov"] = float(c.fov)
    for key in CAMERA_OPTIONAL:
        v = getattr(c, key)
        if v is not None and v != _CAMERA_DEFAULTS.get(key):
            cam[key] = v
    if c.motion:
        cam["motion"] = [{"position": _vec(st.position), "look_at": _vec(st.look_at),
                          "up": _vec(st.up)} for st in c.motion]
    data["shapes"] = [_shape_data(sd, d.base_dir) for sd in d.shapes]
    if d.prototypes:
        data["prototypes"] = {name: [_shape_data(sd, d.base_dir) for sd in shapes]
                              for name, shapes in d.prototypes.items()}
    for ld in d.lights:
        kind = str(ld.kind).split(".")[-1].lower()
        lt = {"type": kind}
        for k in _LIGHT_KEYS[kind]:
            v = getattr(ld, k)
            if v is None:
                continue
            lt[k] = _vec(v) if isinstance(v, (list, tuple, np.ndarray)) else v
        if kind == "environment" and lt.get("file"):
            lt["file"] = os.path.join(d.base_dir, lt["file"])  # as the meshes' files
        data["lights"].append(lt)
    if d.media:
        data["media"] = {name: _medium_data(m) for name, m in d.media.items()}
        for m in data["media"].values():
            if m.get("file"):  # a grid's file, absolute as the meshes' files
                m["file"] = os.path.join(d.base_dir, m["file"])
    if d.world_medium:
        data["world_medium"] = d.world_medium
    r = d.render
    data["render"] = {"integrator": r.integrator, "spp": int(r.spp),
                      "time_budget": float(r.time_budget_s), "max_depth": int(r.max_depth),
                      "seed": int(r.seed)}
    if r.adaptive_threshold > 0.0:
        data["render"]["adaptive_threshold"] = float(r.adaptive_threshold)
        data["render"]["adaptive_min_samples"] = int(r.adaptive_min_samples)
    if r.film_transparent:
        data["render"]["film_transparent"] = True
    if r.motion_blur is not None:
        mb = r.motion_blur
        data["render"]["motion_blur"] = {"enabled": bool(mb.enabled),
                                         "shutter": float(mb.shutter),
                                         "position": mb.position}
        if mb.curve:
            data["render"]["motion_blur"]["curve"] = [float(v) for v in mb.curve]
    return data


# The keys of the media (FORMAT.md "media"), as the JSON writer names them.
_MEDIUM_KEYS = ("sigma_a", "sigma_s", "g", "emission", "density", "color", "absorption_color",
                "file", "grid")
_GRID_KEYS = ("file", "grid")  # the grid kind's own (a homogeneous medium has none)


def _medium_desc(m):
    """A medium dict of the scene format -> facet.MediumDesc (a grid's `transform`: 4 rows)."""
    md = facet.MediumDesc(m["kind"], **{k: v for k, v in m.items()
                                        if k not in ("kind", "transform")})
    if m.get("transform") is not None:
        md.transform = np.asarray(m["transform"], dtype=np.float64)
    return md


def _medium_data(m):
    """facet.MediumDesc -> a medium dict of the scene format (the fields that are set)."""
    out = {"kind": str(m.kind).split(".")[-1].lower()}
    for k in _MEDIUM_KEYS:
        if k in _GRID_KEYS and out["kind"] != "grid":
            continue
        v = getattr(m, k, None)
        if v is not None and not (isinstance(v, str) and not v):
            out[k] = _vec(v) if isinstance(v, (list, tuple, np.ndarray)) else v
    t = getattr(m, "transform", None)
    if t is not None:
        out["transform"] = np.asarray(t, dtype=np.float64).tolist()
    return out


def _texture_values(raw, base_dir):
    """The texture-valued parameters ({"texture": ...} or {"checker": ...}) of a raw JSON
    material, image paths made absolute (relative ones are relative to the scene file)."""
    out = {}
    for k, v in raw.items():
        if isinstance(v, dict) and ("texture" in v or "checker" in v):
            v = dict(v)
            if isinstance(v.get("texture"), str):
                v["texture"] = os.path.join(base_dir, v["texture"])
            out[k] = v
    return out


def read_scene(path):
    """A JSON scene file -> scene data (the core's reader: its errors name file and pointer).
    Texture-valued material parameters are taken from the file as written (the Python
    MaterialDesc carries a texture's file only, not its options), with absolute paths."""
    data = from_description(facet.read_scene_description(path))
    with open(path, encoding="utf-8") as f:
        raw = json.load(f)
    base_dir = os.path.dirname(os.path.abspath(path))
    raw_mats = raw.get("materials", {})
    if isinstance(raw_mats, dict):
        for name, m in data["materials"]:
            if isinstance(raw_mats.get(name), dict):
                m.update(_texture_values(raw_mats[name], base_dir))
    for s, rs in zip(data["shapes"], raw.get("shapes", [])):
        if isinstance(s.get("material"), dict) and isinstance(rs.get("material"), dict):
            s["material"].update(_texture_values(rs["material"], base_dir))
    return data


def write_scene(data, path):
    """Scene data -> JSON scene file (the core's writer)."""
    facet.write_scene_file(to_description(data), path)


def build(data, name="blender"):
    """Scene data -> (renderable facet scene, [warning lines])."""
    scene = facet.build_scene(to_description(data), name=name)
    return scene, list(scene.warnings)


def render_aovs(scene, passes, spp=16, seed=0, threads=0):
    """The core's first-hit passes (facet/render/aov.h) of a built scene: {name: float32
    (h, w, 3), top row first} for names in albedo, normal, depth, emission."""
    return {k: np.asarray(v, dtype=np.float32)
            for k, v in facet.render_aovs(scene, list(passes), spp=int(spp), seed=int(seed),
                                          threads=int(threads)).items()}


def denoise_halves(scene, half_a, half_b, spp, seed, threads=0):
    """The core's denoiser (facet/render/denoise.h, denoise_halves) on the two half-buffers
    (float32 (h, w, 3), top row first) of a render of the built scene at spp and seed: its
    features rendered, then denoised."""
    return np.asarray(facet.denoise_halves(scene, half_a, half_b, int(spp), int(seed),
                                           threads=int(threads)), dtype=np.float32)


class Session:
    """A facet.RenderSession; render() releases the GIL (the binding does) and calls
    on_pass(samples_done, samples_target, elapsed_s, eta_s) -> bool after each pass on the
    calling thread."""

    def __init__(self, scene, spp=None, threads=0, seed=None, max_depth=None, integrator=None,
                 time_budget=None, region=None, light_selection=None, samples=None,
                 adaptive_threshold=None, shadow_catcher_pass=False, depth_pass=False):
        kw = {"threads": int(threads)}
        if shadow_catcher_pass:  # image() is then Cycles' Combined with that pass (render.h)
            kw["shadow_catcher_pass"] = True
        if depth_pass:  # depth(): the Depth pass of the render's camera samples
            kw["depth_pass"] = True
        if adaptive_threshold is not None:  # None: the scene's (its render settings)
            kw["adaptive_threshold"] = float(adaptive_threshold)
        if samples is not None:
            kw["samples"] = tuple(int(v) for v in samples)  # [s0, s1) of the spp-sample render
        if light_selection is not None:
            kw["light_selection"] = light_selection  # "auto" | "view" | "power" | "uniform" | "tree"
        if region is not None:
            kw["region"] = tuple(int(v) for v in region)  # (x0, y0, x1, y1), y down
        if spp is not None:
            kw["spp"] = int(spp)
        if seed is not None:
            kw["seed"] = int(seed)
        if max_depth is not None:
            kw["max_depth"] = int(max_depth)
        if integrator:
            kw["integrator"] = integrator
        if time_budget is not None:
            kw["time_budget"] = float(time_budget)
        self._scene = scene  # the session needs the scene alive
        self._s = facet.RenderSession(scene, **kw)

    def render(self, on_pass):
        def cb(info):
            return bool(on_pass(int(info.samples_done), int(info.samples_target),
                                float(info.elapsed_s), float(info.eta_s)))
        return self._s.render(cb)

    def cancel(self):
        self._s.cancel()

    def image(self):
        """float32 (h, w, 3), top row first (the region's, for a region render)."""
        return np.asarray(self._s.image(), dtype=np.float32)

    def shadow_catcher_pass(self):
        """The Shadow Catcher pass, float32 (h, w, 3), top row first."""
        return np.asarray(self._s.shadow_catcher_pass(), dtype=np.float32)

    def depth(self):
        """The Depth pass summed while rendering (depth_pass=True), float32 (h, w), top row
        first; None when the scene does not allow it (motion blur, ray visibility: then
        passes.write renders it)."""
        d = self._s.depth()
        return None if d is None else np.asarray(d, dtype=np.float32)[:, :, 0]

    def part(self):
        """The facet.RenderPart this session rendered (its sample range)."""
        return self._s.part()

    def mean_spp(self):
        """The samples per pixel taken on average (below spp where adaptive sampling
        stopped tiles early)."""
        return float(self._s.stats.mean_spp)


def merged_shadow_catcher_pass(parts):
    """The Shadow Catcher pass of the render the parts (facet.RenderPart) make up together,
    float32 (h, w, 3), top row first."""
    return np.asarray(facet.merge_parts(list(parts), shadow_catcher_pass=True)[1],
                      dtype=np.float32)
