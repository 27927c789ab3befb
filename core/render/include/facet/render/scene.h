// The renderer's scene: geometry (Embree behind a private implementation), camera, lights,
// materials and render settings, loaded from the JSON scene format (scenes/FORMAT.md).
//
// Conventions:
//  - World space is right-handed, units are whatever the scene uses (metres unless stated);
//    radiometric quantities are in W, W/m^2, W sr^-1 m^-2 (see light.h).
//  - SurfaceHit::ng is the unit GEOMETRIC normal as the shape defines it, NOT flipped toward the
//    ray: outward for spheres, boxes and icospheres; cross(p1 - p0, p2 - p0) for triangles
//    (counter-clockwise winding seen from the front); the shape's +normal for planes, quads and
//    discs; all of them reversed when the shape sets "flip_normals" (an inside-out sphere
//    reflects and emits toward its centre). Transforms never turn a shape inside out: a
//    mirroring transform (negative determinant) keeps the authored front side. `ns` is the unit
//    shading normal (interpolated vertex normals for meshes that have
//    them, else ns = ng), always in ng's hemisphere; an interpolated one is bent for the ray that
//    found the hit (ray_side_valid_normal, shading_normal.h) so that its reflection of the view
//    direction leaves the surface: no hit shades black because of its normal. `dpdu` is a tangent
//    hint for anisotropic models (sphere: direction of increasing longitude about the shape's local
//    z axis; planes, quads, discs and boxes: the shape's local x axis; meshes: 0, use any tangent).
//    On shapes whose material has a normal map (ShapeInfo::needs_tangent) it is the tangent of the
//    UV map instead, with `tangent_sign` (scenes/FORMAT.md, "Normal maps"): the unit dp/du of an
//    analytic shape's UVs, or a mesh's interpolated per-corner tangent (given, or MikkTSpace's:
//    mesh.h), so that the bitangent along +v is tangent_sign * cross(ns, dpdu).
//  - `uv` holds the shape's texture coordinates (scenes/FORMAT.md, "UV coordinates") only on
//    shapes whose material or emission is textured (ShapeInfo::needs_uv); elsewhere it is not
//    computed (skip what the scene does not need) and must not be read. `textured` >= 0 means
//    the material's parameters depend on uv: build the hit's material with
//    Scene::material_at(hit) instead of using `material` (the untextured fast path).
//    `dpdu_uv`, `dpdv_uv` (the partial derivatives of p with respect to u and v, world units
//    per unit of uv) are filled with uv and give the texture footprint (uv_footprint):
//    triangles, per triangle from its vertices' positions and uvs (pbrt-v4 eq. 6.7; zero when
//    the uvs are degenerate: no filtering); sphere and icosphere, the longitude/latitude map's
//    derivatives 2 pi (-y, x, 0) and pi (-z x / rho, -z y / rho, rho) in object space
//    (rho = sqrt(x^2 + y^2)); disc, 2 x and 2 y of its object frame; plane, its unit uv axes.
//  - `color` is the hit's vertex colour (linear RGBA, barycentric over the triangle's corners:
//    mesh.h) only on shapes whose material or emission reads one (ShapeInfo::needs_color);
//    elsewhere it is (1, 1, 1, 1) and not computed.
//  - Curves (ShapeKind::Curves): `ng` = `ns` is the unit normal of the tube at the hit (round:
//    from the axis point at the hit's curve parameter to the hit point; flat, a ribbon facing
//    the ray: the normal a round tube of the same radius would have at the hit's position across
//    the ribbon, as Cycles shades ribbons), `dpdu` the unit tangent of the axis (toward the
//    tip), `uv` the strand's root texture coordinates (with needs_uv; dp/du and dp/dv of uv are
//    0: uv is constant along a strand). `strand_v` is the position along the strand (0 at its
//    first segment's start, 1 at its last segment's end, uniform in the curve parameter per
//    segment) and `strand_h` = round(32767 h), h = dot(ng, cross(w, dpdu)) in [-1, 1] the
//    position across it (w: the unit direction toward the ray origin made normal to dpdu;
//    Chiang et al. 2016's h, Cycles' sign); both are written on curve hits only (they sit in
//    padding). `strand_random` is the strand's random value (curve_random of its index in
//    the shape), written on curve hits of shapes whose textures read it
//    (ShapeInfo::needs_strand) only; it shares tangent_sign's place (curves have no tangent
//    space: a normal map on curves is an error), so SurfaceHit keeps its size.
//  - `emitter_prim`, on hits of a moving emitter's triangles only (an emitting triangle shape
//    with motion: its instance moves or deforms), is the triangle's index in its mesh, which
//    the light's pdf needs (Light::pdf_li_at); it shares strand_v's place (curves do not emit).
//  - `po` is the hit point in the shape's object space (its transform's inverse; for a
//    prototype's shape, its own frame within the prototype) only on shapes whose material or
//    emission has a procedural texture reading object or generated coordinates
//    (ShapeInfo::needs_position); elsewhere it is not computed.
//    On a prototype's shape whose textures read view-dependent coordinates and no position
//    (ShapeInfo::normal_in_po), `po` holds the shading normal in that object space instead
//    (unit, turned to the ray's side: TexturePoint::normal); hits elsewhere derive it from ns.
//  - Sidedness: a surface hit from the back (dot(ng, -ray.d) < 0) reflects as if its normals
//    were flipped when `two_sided` is true; otherwise it is black (reflects nothing). Emission
//    is always one-sided: only the front side emits (light.h).
//  - `emitted_radiance` is the radiance the surface emits toward the ray origin (0 for
//    non-emitters and for the back of an emitter); `light` is the index of the area light in
//    lights() (or -1). Scene::lights() holds every light: area lights too.
//  - Shadow and continuation rays must be spawned with spawn_ray()/shadow_ray()/occluded():
//    they start at offset_ray_origin (precision.h), off the surface along ng by the hit point's
//    error bound `p_err`, so that rounding error never re-hits the surface it leaves; shadow
//    rays to a point on an area light end off the light by the sample's own bound.
//  - After load_scene() the Scene is immutable; every const member is thread-safe.
//  - Errors: load_scene* throw SceneError whose what() is "<file>: <JSON pointer>: <message>"
//    (e.g. "scene.json: /shapes/3/material: unknown material 'glosy' (did you mean 'glossy'?)").
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "facet/bxdf.h"
#include "facet/material.h"
#include "facet/registry.h"
#include "facet/render/camera.h"
#include "facet/render/light.h"
#include "facet/render/medium.h"
#include "facet/render/motion.h"
#include "facet/render/precision.h"
#include "facet/render/texture.h"
#include "facet/staged_material.h"
#include "facet/types.h"

namespace facet::render {

class SceneError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

struct SurfaceHit {
    float t = kInfinity;  // ray parameter of the hit
    Vec3 p{0.f};          // hit point (world space)
    Vec3 p_err{0.f};      // error box of p (precision.h): p +- p_err meets the surface
    Vec3 ng{0.f};         // unit geometric normal (see conventions: not flipped)
    Vec3 ns{0.f};         // unit shading normal, same hemisphere as ng
    Vec3 dpdu{0.f};       // tangent hint, may be 0
    union {
        float tangent_sign = 1.f;  // bitangent sign (only where ShapeInfo::needs_tangent)
        float strand_random;       // curves, which have no tangent space (see conventions)
    };
    std::uint32_t shape = 0;             // index into Scene::shapes()
    const Material* material = nullptr;  // never null for a hit
    Rgb emitted_radiance{0.f};           // radiance emitted toward the ray origin
    bool two_sided = true;               // see conventions
    std::int16_t strand_h = 0;           // curves: across the strand (see conventions)
    // Index into Scene::lights() when the shape emits, else -1 (kEmitterNotSampled: it emits
    // and is no light source).
    std::int32_t light = -1;
    Vec2 uv{0.f};                     // texture coordinates (see conventions)
    std::int32_t textured = -1;       // index of the textured material, or -1
    Vec3 dpdu_uv{0.f}, dpdv_uv{0.f};  // dp/du and dp/dv (with uv; see conventions)
    glm::vec4 color{1.f};             // vertex colour (see conventions)
    Vec3 po{0.f};                     // object-space point (see conventions)
    union {
        float strand_v = 0.f;        // curves: along the strand (see conventions)
        std::uint32_t emitter_prim;  // a moving emitter's hit: its triangle (Light::pdf_li_at)
    };

    // Curves: the hit's position across its strand, h in [-1, 1] (see conventions).
    float strand_across() const { return float(strand_h) * (1.f / 32767.f); }
};

// Cycles 3.4's random value of strand i of a hair geometry (blender/curves.cpp: the curve
// attribute Random, hash_uint2_to_float(i, 0), lookup3's hash as in the textures), in [0, 1]:
// what Blender's Hair Info Random and an unlinked Principled Hair Random read.
float curve_random(std::uint32_t i);

// The footprint in uv of pixel footprint fp at a hit with derivatives dpdu, dpdv: the least
// squares solution of dpdx = dpdu dudx + dpdv dvdx (and likewise for y), as pbrt-v4's
// SurfaceInteraction::ComputeDifferentials; zero when dpdu and dpdv are degenerate.
UvFootprint uv_footprint(const PixelFootprint& fp, const Vec3& dpdu, const Vec3& dpdv);

struct RenderSettings {
    std::string integrator = "path";  // "direct" | "path"
    int spp = 16;                     // samples per pixel (>= 1)
    double time_budget_s = 0.0;       // > 0: render until the budget is spent (spp is then a cap)
    int max_depth = 8;  // maximum path depth in bounces (>= 0; 0 = only what camera rays see)
    std::uint64_t seed = 0;
    // Adaptive sampling (render.h): the noise threshold (0 = off) and the samples every pixel
    // takes first (0 = automatic).
    double adaptive_threshold = 0.0;
    int adaptive_min_samples = 0;
    int width = 0, height = 0;  // copied from the camera
    // Motion blur (scenes/FORMAT.md, "Motion blur"; facet/render/motion.h). Absent or not
    // `enabled`: every motion is rendered at the frame's time (a still). `shutter`: the open
    // time in frames (> 0); `position`: where the frame's time lies in it ("start", "center",
    // "end", as Blender's Position); `curve`: the shutter curve's weights on equal cells of
    // the open interval (empty: uniform). The motion steps span the open interval.
    struct MotionBlur {
        bool enabled = true;
        double shutter = 0.5;
        std::string position = "center";
        std::vector<double> curve;
        bool operator==(const MotionBlur&) const = default;
    };
    std::optional<MotionBlur> motion_blur;
    // Film > Transparent (scenes/FORMAT.md, "Film transparency and holdouts"): the environment
    // that camera rays see directly or through transparent surfaces is left out of the colour
    // and the image gets an alpha channel, 1 - the fraction of the pixel where it shows.
    bool film_transparent = false;
    bool operator==(const RenderSettings&) const = default;
};

enum class ShapeKind : std::uint8_t {
    Sphere,
    Plane,
    Box,
    Quad,
    Disc,
    Mesh,
    Icosphere,
    Grid,
    Gltf,
    Instance,
    Curves
};

// A surface's opacity (scenes/FORMAT.md, "Opacity"), for cut-outs: the fraction alpha in
// [0, 1] of the rays meeting the surface that stop there; the others pass through as if it were
// not there (camera, continuation and shadow rays alike). alpha is `value`, or the texture's
// value (its r channel) at the hit's uv; with a `cutoff` > 0 (glTF's alphaMode MASK) it becomes
// 1 where that value is >= cutoff and 0 elsewhere. Decided per candidate hit while tracing
// (embree_scene.cpp), with the hit's random number u from hash_uniform (precision-free, no
// sampler dimension): the surface is there when opacity_blocks(alpha, u).
struct Opacity {
    float value = 1.f;
    const Texture* texture = nullptr;  // instead of `value`, or null
    float cutoff = 0.f;                // > 0: alpha = value >= cutoff ? 1 : 0
    // Whether the surface can let a ray through (else it is opaque: the fast path).
    bool active() const { return texture != nullptr || value < 1.f; }
    float alpha(Vec2 uv) const {
        const float a = texture ? texture->eval(uv).r : value;
        return cutoff > 0.f ? (a >= cutoff ? 1.f : 0.f) : a;
    }
};

// Whether a ray meets a surface of opacity alpha, given u uniform in [0, 1): with probability
// alpha. alpha = 0 never blocks, alpha = 1 always does (exact holes and exact solids).
[[gnu::always_inline]] inline bool opacity_blocks(float alpha, float u) {
    return u < alpha;
}

// Ray visibility (scenes/FORMAT.md, "Ray visibility"; Blender's Object > Visibility > Ray
// Visibility as Cycles 3.4 applies it): the kinds of ray a shape is there for. A ray the shape
// is invisible to passes through it as if it were not there (no vertex, no emission; a shadow
// ray is not blocked). A ray's kind is what made it (integrator.h, "Ray visibility"): the
// camera (also through transparent surfaces), a diffuse, glossy (or mirror) reflection, any
// transmission, a scattering in a medium (which Cycles also lets see what diffuse rays see),
// or next-event estimation (shadow).
enum RayVisibility : std::uint8_t {
    kRayCamera = 1u << 0,
    kRayDiffuse = 1u << 1,
    kRayGlossy = 1u << 2,
    kRayTransmission = 1u << 3,
    kRayVolumeScatter = 1u << 4,
    kRayShadow = 1u << 5,
    kRayAll = (1u << 6) - 1u
};
// The names of the bits in JSON (`"visibility": {"camera": false, ...}`), bit i = 1 << i.
inline constexpr std::array<const char*, 6> kRayVisibilityNames = {
    "camera", "diffuse", "glossy", "transmission", "volume_scatter", "shadow"};
// ShapeSurface::light of an emitter that is no light source: a shape invisible to diffuse,
// glossy and transmission rays (Cycles 3.4 then leaves it out of light sampling; camera rays
// still see its emission).
inline constexpr std::int32_t kEmitterNotSampled = -2;

// Light Path switches (scenes/FORMAT.md, "Light Path switches"; Blender's Light Path node as a
// Mix Shader's Fac): the ray outputs Cycles 3.4 sets for the ray that reaches a surface. A
// camera ray (also through transparent surfaces) is a camera ray; a ray after a bounce is a
// reflection or a transmission and diffuse, glossy or (a delta lobe) glossy and singular; a
// shadow ray of light sampling is a shadow ray and nothing else; after a medium's scattering,
// and for the emission that light sampling reads, every output is 0.
enum LightPathRay : std::uint8_t {
    kLpCamera = 1u << 0,
    kLpShadow = 1u << 1,
    kLpDiffuse = 1u << 2,
    kLpGlossy = 1u << 3,
    kLpSingular = 1u << 4,
    kLpReflection = 1u << 5,
    kLpTransmission = 1u << 6
};
// The outputs' names in JSON (`"ray": "camera"`), bit i = 1 << i.
inline constexpr std::array<const char*, 7> kLightPathRayNames = {
    "camera", "shadow", "diffuse", "glossy", "singular", "reflection", "transmission"};
// A shape's switch: the first entry whose output is 1 for a ray gives the ray's hit its
// material and emission (radiance, front side only) instead of the shape's; rays no entry
// matches see the shape's own. Shadow rays pass an entry's material when rays pass it (a
// `null` surface), else it blocks them.
struct LightPathSwitch {
    struct Entry {
        std::uint8_t ray = 0;  // one LightPathRay bit
        const Material* material = nullptr;
        Rgb emission{0.f};
    };
    std::vector<Entry> entries;
};

// What a hit on a surface reads: its material, emission and sidedness.
struct ShapeSurface {
    std::string material_name;  // the "materials" key, "<inline>", or the part's source
    const Material* material = nullptr;
    Rgb emission{0.f};        // radiance; non-zero makes the surface an area light
    std::int32_t light = -1;  // index into lights() when emissive (or kEmitterNotSampled)
    bool two_sided = true;
    std::int32_t textured = -1;  // index of its textured material (Scene::material_at), or -1
    const Texture* emission_texture = nullptr;  // textured emission (times nothing), or null
    Opacity opacity;                            // its material's (Opacity::active: a cut-out)
    bool holdout = false;  // the shape's `holdout` flag (read by the alpha kernels only)
    // The shape's `shadow_catcher` flag (read by the alpha kernels only, in scenes with one:
    // SceneFeatures::has_shadow_catcher).
    bool shadow_catcher = false;
    // The shape's `visibility` (its parts': unused): the RayVisibility bits of the rays that see
    // it (read by the media kernel only, which
    // scenes with SceneFeatures::has_ray_visibility run).
    std::uint8_t visibility = kRayAll;
    // The shape's Light Path switch (an index into Scene::light_paths()), or -1 (read by the
    // media kernel only, like `visibility`).
    std::int32_t light_path = -1;
};

// One entry per element of the scene file's "shapes" array, in file order. A shape whose kind
// brings its own materials (gltf: one per primitive) has `parts`, each a surface of its own;
// its triangles name their part (the shape's own surface fields then are unused: black).
// The shapes of the prototypes (SceneDescription::prototypes) follow, prototype by prototype in
// description order: hits on an instance name the prototype's shape (an instance's own entry,
// kind Instance, is never hit).
struct ShapeInfo : ShapeSurface {
    ShapeKind kind = ShapeKind::Mesh;
    std::uint64_t triangles = 0;  // 0 for the analytic shapes (sphere, plane, disc)
    std::vector<ShapeSurface> parts;
    bool needs_uv = false;  // hits compute uv (textured material/emission)
    // Hits compute the UV map's tangent frame (dpdu, tangent_sign): the material has a normal
    // map. Implies needs_uv.
    bool needs_tangent = false;
    // Hits interpolate the mesh's vertex colours (SurfaceHit::color): a vertex_color texture.
    bool needs_color = false;
    // Hits compute the object-space point (SurfaceHit::po): a procedural texture reads object
    // or generated coordinates. `to_object` maps world space (a prototype's shape: the
    // prototype's frame) to object space; the texture space maps po to Blender's Generated
    // coordinates, generated = (po - texture_lo) * texture_inv (ShapeDesc::texture_space).
    bool needs_position = false;
    // Hits compute the object-space normal (SurfaceHit::no) and their texture points the
    // view-dependent coordinates (TexturePoint::normal, ...): a procedural texture reads
    // normal, reflection, camera or window coordinates. `normal_to_object` maps world-space
    // normals (a prototype's shape: in the prototype's frame) to object space, transpose of the
    // inverse of to_object's linear part.
    bool needs_view = false;
    // Hits on its curves write their strand's random value (SurfaceHit::strand_random) and
    // their texture points the Hair Info values (TexturePoint::strand_random, ...): a texture
    // reads them (kTextureReadsStrand).
    bool needs_strand = false;
    // A prototype's shape with needs_view: its hits keep the object-space normal in
    // SurfaceHit::po (the instance's transform is not known after the hit).
    bool normal_in_po = false;
    glm::mat3 normal_to_object{1.f};
    glm::dmat4 to_object{1.0};
    Vec3 texture_lo{-1.f}, texture_inv{0.5f};
};

// A material some of whose parameters are textures: the model and its constant parameters, and
// for each textured parameter the texture and whether the model reads it as a colour. At a hit
// the textures are evaluated into a block of values and the model's lobes are set from them by
// its staged build (`staged`, facet/staged_material.h): no allocation and no string handling
// per hit. `model`, `params` and `convert` describe the material as the registry builds it from
// constants (make_material): the reference the staged build is tested against.
struct TexturedMaterial {
    std::string model;
    ParamSet params;  // the constant parameters and a placeholder for every textured one
    struct Slot {
        std::string name;
        const Texture* texture;
        bool color;  // a colour parameter (else a number: the texture's r channel)
    };
    std::vector<Slot> slots;
    // A kind's own parameterisation (glTF's metallic-roughness: io/gltf_import.cpp): `params` and
    // the slots then hold its source values, which `convert` maps onto the model's parameters
    // at every hit (pure, never throws). Null: the slots are the model's parameters.
    using Convert = ParamSet (*)(const ParamSet&);
    Convert convert = nullptr;
    // The staged build (facet/staged_material.h).
    //  - Without a conversion, value i of `staged` is slot i's (a number: its r channel).
    //  - With one, `convert_values` maps the sources (`sources`: the constants, slot i's value
    //    at sources[slot_source[i]]) onto `staged`'s values, as `convert` does on ParamSets.
    static constexpr std::size_t kMaxStaged = ParamValues::kMax;  // values or sources
    std::shared_ptr<const StagedMaterial> staged;
    using ConvertValues = void (*)(const DVec3* sources, DVec3* outputs);
    ConvertValues convert_values = nullptr;
    std::vector<DVec3> sources;
    std::vector<std::uint8_t> slot_source;
    std::size_t num_staged = 0;  // number of staged values
    // Union of the lobes of the material at its textures' extremes (every corner of the
    // slots' [min, max] box with a conversion; both ends otherwise), for the scene analysis:
    // a roughness texture can make a lobe a mirror at some texels and glossy at others.
    BxDFFlags flags = BxDFFlags::None;
    // Normal map (scenes/FORMAT.md, "Normal maps"): a linear RGB texture, its strength; null
    // when the material has none (Scene::shade_normal does nothing then).
    const Texture* normal_map = nullptr;
    float normal_strength = 1.f;
    float normal_xy_scale = 1.f;  // glTF's normalTexture.scale
    // Bump map (scenes/FORMAT.md, "Bump maps"): the height texture (number: its r), Blender's
    // distance and strength, and the forward-difference step in uv; null when the material
    // has none.
    const Texture* bump = nullptr;
    float bump_distance = 1.f, bump_step = 1e-3f, bump_strength = 1.f;
    // Set when the only textured parameter is a diffuse reflectance (lambert "reflectance",
    // composite "diffuse_reflectance"): the material built at the texture's largest value, whose
    // diffuse lobe material_at replaces per hit (Material::with_diffuse_reflectance): the same
    // bits as the staged build, without building the other lobes again.
    const Material* diffuse_base = nullptr;
    bool diffuse_black_ok = false;  // lambert: a black value is still its one lobe
    // The sub-materials of a combination (mix, add), in order: a constant material, or
    // (textured >= 0) another textured material built at the same hit.
    struct Child {
        std::shared_ptr<const Material> constant;
        std::int32_t textured = -1;
    };
    std::vector<Child> children;
    // Whether a slot (or a child's) reads the hit's uv / its vertex colour (Texture::uses_uv,
    // uses_vertex_color; the normal and bump maps always read uv).
    bool uses_uv = false, uses_color = false;
    // Whether a slot (or a child's) reads the hit's object-space point (Texture::uses_position)
    // / its view-dependent coordinates (Texture::uses_view).
    bool uses_position = false, uses_view = false;
    // Whether a slot (or a child's) reads the Hair Info values (Texture::uses_strand) / the
    // ray's Light Path state (Texture::uses_ray).
    bool uses_strand = false, uses_ray = false;
};

// What the scene contains, computed once at load time; integrators pick a specialised kernel
// from it and `facet render --explain` prints it.
struct SceneFeatures {
    BxDFFlags lobes = BxDFFlags::None;  // union of every material's Material::flags()
    bool has_diffuse = false, has_glossy = false, has_specular = false;
    bool has_transmission = false;  // some material transmits (facet/dielectric.h)
    // Some surface's material is textured (ShapeSurface::textured >= 0): only then do kernels
    // test SurfaceHit::textured and build per-hit materials (kFeatTextured).
    bool has_textured = false;
    // The scene has a world medium or a surface that bounds a medium or lets rays through (a
    // material with an "interior", or the `null` model): only then does the media kernel run
    // (integrator.h, kFeatMedia).
    bool has_media = false;
    // Some material has a subsurface lobe (Material::subsurface()): the volumetric path kernel
    // runs, which walks inside such objects (integrator.h, "Subsurface").
    bool has_subsurface = false;
    // Motion blur is on and something moves (a camera or shape `motion`): only then do rays
    // carry a time and the motion kernels run (integrator.h, kFeatMotion).
    bool has_motion = false;
    // A holdout: a material with a `holdout` part (Material::has_holdout) or a shape with
    // `holdout` (ShapeInfo::holdout).
    bool has_holdout = false;
    // Some shape is a shadow catcher (ShapeInfo::shadow_catcher): the media kernel runs, with
    // alpha (integrator.h, "Shadow catcher"), and the film keeps the catcher's sums (film.h).
    bool has_shadow_catcher = false;
    // The film is transparent, the scene has a holdout or a shadow catcher: only then do the
    // alpha kernels run
    // (integrator.h, kFeatAlpha). The image has an alpha channel (the film keeps coverage
    // sums) only with RenderSettings::film_transparent: without it holdouts are black, as
    // Cycles' are ("the Holdout shader can only create alpha when Film > Transparent is on").
    bool needs_alpha = false;
    // Some shape is invisible to some kind of ray (ShapeSurface::visibility), has a Light
    // Path switch (ShapeSurface::light_path) or a material that reads the ray's Light Path
    // state (TexturedMaterial::uses_ray): the media kernel runs, which tracks each ray's kind
    // (integrator.h, "Ray visibility").
    bool has_ray_visibility = false;
    bool lambert_only = false;  // every material is a pure Lambertian (diffuse only)
    bool has_point = false, has_spot = false, has_directional = false, has_area = false,
         has_environment = false;
    bool all_lights_delta = true;  // every light is a point, spot or directional light without size
    bool any_non_delta_light = false;  // == !all_lights_delta (when there is any light)
    // An area light or the environment: BSDF-sampled rays can find an emitter (MIS). Lights
    // with size (sphere, sun) are not delta but no ray finds them (light.h).
    bool any_hittable_light = false;
    // Conservative: true unless no emitter (area light, environment) can appear in a primary
    // ray (every emitter's bounds lie outside the view frustum, and no environment).
    bool emitter_visible = false;
    // True when some surface reflects a non-zero fraction of light (some material has a lobe
    // with non-zero reflectance): only then can indirect light exist.
    bool can_reflect = false;
    std::size_t num_lights = 0, num_shapes = 0, num_materials = 0;
    std::uint64_t num_triangles = 0, num_spheres = 0, num_planes = 0, num_discs = 0;

    // Multi-line human-readable summary for --explain.
    std::string describe() const;
};

// What a surface is to media (scenes/FORMAT.md, "Media"), by its material: the medium its
// shape bounds (`interior`, an index into Scene::media(), or -1) and whether rays pass straight
// through it (`pass_through`: the `null` model, an invisible boundary; camera, continuation
// and shadow rays cross it without a vertex). A ray that crosses the surface against its
// geometric normal (dot(d, ng) < 0) enters the interior, along it leaves.
struct MediumInterface {
    const Material* material = nullptr;
    std::int32_t interior = -1;
    bool pass_through = false;
};

// Axis-aligned bounds of the finite geometry (planes excluded).
struct Bounds3 {
    Vec3 lo{kInfinity}, hi{-kInfinity};
    bool empty() const { return !(lo.x <= hi.x); }
};

// Up to 8 rays in structure-of-arrays form, for the packet queries below. The path integrator
// writes each lane's next ray straight into it, component by component (building Ray values
// and copying them cost store-forwarding stalls: 4.5% of the kernel's samples on one such
// copy), and a query copies the arrays into Embree's packet. Lanes never set hold a harmless
// ray (origin 0, +z, tmax 0).
struct RayPacket {
    static constexpr std::size_t kSize = 8;
    alignas(32) float ox[kSize], oy[kSize], oz[kSize];
    float dx[kSize], dy[kSize], dz[kSize], tmax[kSize];
    // Each lane's shutter time (motion.h). set() and get() leave it: a lane keeps the time of
    // its path while its rays change (the motion kernels set it once per camera sample).
    // Embree reads it only in scenes that move (Scene::intersect_packet).
    float time[kSize];

    RayPacket() {
        for (std::size_t k = 0; k < kSize; ++k) {
            ox[k] = oy[k] = oz[k] = dx[k] = dy[k] = tmax[k] = time[k] = 0.f;
            dz[k] = 1.f;
        }
    }
    void set(std::size_t k, const Ray& r) {
        ox[k] = r.o.x;
        oy[k] = r.o.y;
        oz[k] = r.o.z;
        dx[k] = r.d.x;
        dy[k] = r.d.y;
        dz[k] = r.d.z;
        tmax[k] = r.tmax;
    }
    Vec3 origin(std::size_t k) const { return {ox[k], oy[k], oz[k]}; }
    Vec3 direction(std::size_t k) const { return {dx[k], dy[k], dz[k]}; }
    Ray get(std::size_t k) const { return {origin(k), direction(k), tmax[k]}; }
};

class Scene {
  public:
    Scene();
    ~Scene();
    Scene(Scene&&) noexcept;
    Scene& operator=(Scene&&) noexcept;
    Scene(const Scene&) = delete;
    Scene& operator=(const Scene&) = delete;

    // Closest hit along the ray with t in (0, ray.tmax]. Fills `hit` and returns true, or
    // returns false and leaves `hit` untouched.
    bool intersect(const Ray& ray, SurfaceHit& hit) const;
    // The same at shutter time `time` in [0, 1) (motion blur, motion.h: moving instances are
    // placed at that time).
    bool intersect(const Ray& ray, float time, SurfaceHit& hit) const;
    // Closest hits of the first n <= kPacketSize rays of a packet in one Embree packet query
    // (rtcIntersect8): found[k] and hits[k] as intersect(rays.get(k), hits[k]) would give them,
    // for the rays with active[k] (every ray when `active` is null; the others' entries are left
    // untouched). Cheaper than ray by ray: measured 1.3-1.5x on incoherent path-tracer rays,
    // more on the camera rays of neighbouring pixels.
    void intersect_packet(const RayPacket& rays, std::size_t n, SurfaceHit* hits, bool* found,
                          const bool* active = nullptr) const;
    // Occlusion of the first n <= kPacketSize rays of a packet in one packet query
    // (rtcOccluded8): blocked[k] is true when something lies on ray k with t in (0, tmax), for
    // the rays with active[k] (the others, and rays with tmax <= 0, get false). The rays come
    // from shadow_ray()/spawn_ray().
    void occluded_packet(const RayPacket& rays, std::size_t n, const bool* active,
                         bool* blocked) const;
    static constexpr std::size_t kPacketSize = RayPacket::kSize;
    // A ray leaving surface point p (error box p_err, geometric normal ng of either orientation)
    // in unit direction d: origin offset_ray_origin(p, p_err, ng, d) (precision.h), tmax = inf.
    static Ray spawn_ray(const Vec3& p, const Vec3& p_err, const Vec3& ng, const Vec3& d);
    [[gnu::always_inline]] static Ray spawn_ray(const SurfaceHit& hit, const Vec3& d) {
        return spawn_ray(hit.p, hit.p_err, hit.ng, d);
    }
    // The shadow ray of light sample `ls` from ray origin o, a point already offset off its
    // surface toward the light (offset_ray_origin). For a light at a finite distance the ray
    // ends off the light's surface too, offset by the sample's own error box toward o
    // (pbrt-v4's SpawnRayTo), so the light's own surface never shadows its sample at any angle;
    // it stops kShadowEpsilon of its length short of that end (a point light, n_light = 0 and
    // no error box, is its own end). Directional and environment lights: a ray toward ls.wi.
    // Unit direction; tmax <= 0: nothing to test.
    static Ray shadow_ray_from(const Vec3& o, const LightLiSample& ls);
    // The same from surface hit `hit`: the origin offset off hit's surface toward ls.wi.
    [[gnu::always_inline]] static Ray shadow_ray(const SurfaceHit& hit, const LightLiSample& ls) {
        return shadow_ray_from(offset_ray_origin(hit.p, hit.p_err, hit.ng, ls.wi), ls);
    }
    // Whether something blocks shadow_ray(hit, ls).
    [[gnu::always_inline]] bool occluded(const SurfaceHit& hit, const LightLiSample& ls) const {
        const Ray r = shadow_ray(hit, ls);
        return r.tmax > 0.f && occluded_ray(r);
    }
    // The same at shutter time `time` (motion blur: RayPacket::time).
    bool occluded(const SurfaceHit& hit, const LightLiSample& ls, float time) const {
        const Ray r = shadow_ray(hit, ls);
        return r.tmax > 0.f && occluded_ray_at(r, time);
    }
    // Shadow ray from an exactly known point p (error box: its own rounding) with geometric
    // normal ng toward unit direction wi over distance dist (may be +inf; a finite ray stops
    // kShadowEpsilon of dist short of its end). True when something blocks it.
    bool occluded(const Vec3& p, const Vec3& ng, const Vec3& wi, float dist) const;

    const Camera& camera() const { return m_camera; }
    // Motion blur (motion.h), read by the motion kernels only (SceneFeatures::has_motion): the
    // camera's steps (none when it does not move; camera() is then the camera) and the density
    // the ray time is drawn from.
    const CameraMotion& camera_motion() const { return m_camera_motion; }
    const ShutterCurve& shutter() const { return m_shutter; }
    std::span<const Light> lights() const { return m_lights; }
    // Next-event estimation's choice of light, in proportion to power (light.h).
    const LightDistribution& light_distribution() const { return m_light_distribution; }
    // The choice in proportion to the lights' contributions measured from the camera
    // (LightDistribution::view; RenderOptions::light_selection View, the default).
    const LightDistribution& view_light_distribution() const { return m_view_light_distribution; }
    // The environment light, or null when the scene has none (escaping rays then see black).
    const Light* environment() const {
        return m_environment >= 0 ? &m_lights[std::size_t(m_environment)] : nullptr;
    }
    // Radiance that camera ray (o, d) sees from the area lamps with "camera_visible" nearer
    // than t_hit (the ray's closest hit, +inf when none). As Cycles 3.4, the lamp is
    // transparent: the ray goes on to what lies behind it, so the caller ADDS this to the
    // radiance found along the ray. 0 (and no work) when no lamp is camera-visible.
    Rgb camera_lamps(const Vec3& o, const Vec3& d, float t_hit) const {
        Rgb l(0.f);
        for (std::uint32_t i : m_camera_lamps)
            if (m_lights[i].camera_hit(o, d) < t_hit) l += m_lights[i].emission();
        return l;
    }
    bool has_camera_lamps() const { return !m_camera_lamps.empty(); }
    // The media (scenes/FORMAT.md, "Media"), indexed by MediumInterface::interior.
    std::span<const Medium> media() const { return m_media; }
    // The index of the medium the camera and escaping rays are in, or -1 (vacuum).
    std::int32_t world_medium() const { return m_world_medium; }
    // The medium interface of a hit's material (SurfaceHit::material), or null for a surface
    // that neither bounds a medium nor lets rays through. A linear search over the few
    // boundary materials: called only by the media kernel.
    const MediumInterface* medium_interface(const Material* m) const {
        for (const MediumInterface& i : m_interfaces)
            if (i.material == m) return &i;
        return nullptr;
    }
    const RenderSettings& settings() const { return m_settings; }
    const SceneFeatures& features() const { return m_features; }
    // The shapes' Light Path switches (ShapeSurface::light_path).
    std::span<const LightPathSwitch> light_paths() const { return m_light_paths; }
    // Per light, the ray visibility of the shape that emits it (kRayAll for lamps); filled
    // only when SceneFeatures::has_ray_visibility (read by the media kernel's light samples).
    std::span<const std::uint8_t> light_visibility() const { return m_light_visibility; }
    std::span<const ShapeInfo> shapes() const { return m_shapes; }
    const Bounds3& bounds() const { return m_bounds; }
    // Radius of a sphere around bounds() (at least 1), for Light::power().
    float radius() const;
    // The file name the scene was loaded from (or the name given for a string).
    const std::string& name() const { return m_name; }
    // fingerprint() of the SceneDescription it was built from (scene_description.h).
    std::uint64_t fingerprint() const { return m_fingerprint; }
    // The one entry from a hit to its BSDF, for every integrator and the AOV pass: a hit with
    // hit.textured >= 0 gets its shading normal (shade_normal: normal and bump maps), its
    // texture footprint (texture_footprint: exact from `ray` when `camera_ray`, else as the
    // camera sees p) and its material (material_at); the result is stored in `storage`. Other
    // hits return *hit.material untouched. Never throws.
    // `rs`: the ray's Light Path state (texture.h RayState), read by light_path textures (the
    // media kernel gives it; null: a camera ray's).
    const Material& bsdf_at(SurfaceHit& hit, const Ray& ray, bool camera_ray,
                            std::optional<Material>& storage, const RayState* rs = nullptr) const {
        if (hit.textured < 0) return *hit.material;
        const Vec3 ns = hit.ns;  // the view-dependent coordinates read the unmapped normal
        shade_normal(hit, -ray.d);
        const UvFootprint fp = texture_footprint(hit, camera_ray ? &ray : nullptr);
        // Built in `storage` itself: the conversion returns a prvalue, so the material is not
        // moved (it is about 1 KB).
        struct AtHit {
            const Scene& scene;
            const SurfaceHit& hit;
            const UvFootprint& fp;
            Vec3 wo, ns;
            const RayState* rs;
            operator Material() const { return scene.material_at(hit, fp, wo, ns, rs); }
        };
        return storage.emplace(AtHit{*this, hit, fp, -ray.d, ns, rs});
    }
    // The material at a hit with hit.textured >= 0: its textures evaluated at hit.uv and the
    // model built from them (never throws: build_scene checked every texture's range against
    // the model's). Hits with textured < 0 use *hit.material. `wo` (unit, toward the viewer)
    // and `ns` (the world-space shading normal before normal and bump maps) are read by
    // view-dependent coordinates only (texture_point).
    Material material_at(const SurfaceHit& hit, const UvFootprint& fp = {},
                         const Vec3& wo = Vec3(0.f), const Vec3& ns = Vec3(0.f),
                         const RayState* rs = nullptr) const;
    // Textured material `index` at uv, as material_at builds it.
    // `color` is the hit's vertex colour (SurfaceHit::color), read by vertex_color textures.
    Material textured_material(std::size_t index, Vec2 uv, const UvFootprint& fp,
                               const glm::vec4& color = glm::vec4(1.f)) const {
        return textured_material(index, TexturePoint{uv, &fp, color});
    }
    // Textured material `index` at texture point p (its footprint non-null).
    Material textured_material(std::size_t index, const TexturePoint& p) const;
    // What textures read at a hit (TexturePoint): its uv, vertex colour, object-space point
    // and generated coordinates, with footprint fp (material_at adds the Hair Info values on
    // curves with ShapeInfo::needs_strand: curves neither emit nor have normal, bump or opacity
    // maps, the other readers); on shapes with ShapeInfo::needs_view also the view-dependent
    // coordinates, from `wo` (unit, toward the viewer), the world-space
    // shading normal `ns` (before normal and bump maps) and the shape's normal_to_object.
    TexturePoint texture_point(const SurfaceHit& hit, const UvFootprint& fp, const Vec3& wo,
                               const Vec3& ns) const {
        const ShapeInfo& s = m_shapes[hit.shape];
        TexturePoint p{hit.uv, &fp, hit.color, hit.po, (hit.po - s.texture_lo) * s.texture_inv};
        if (s.needs_view) [[unlikely]]
            view_coordinates(hit, wo, ns, p);
        return p;
    }
    // Fills p's view-dependent coordinates (TexturePoint) at a hit.
    void view_coordinates(const SurfaceHit& hit, const Vec3& wo, const Vec3& ns,
                          TexturePoint& p) const;
    // The texture footprint of a hit with uv: from the camera ray `camera_ray` that reached it
    // (exact), or for hits of later path vertices (camera_ray null) as the camera would see p
    // (Camera::footprint_at).
    UvFootprint texture_footprint(const SurfaceHit& hit, const Ray* camera_ray) const;
    // The shading normal of a hit with hit.textured >= 0 whose material has a normal map
    // and/or a bump map: hit.ns becomes the mapped normal (Blender's Normal Map node, tangent
    // space), then the bumped one (Blender's Bump node, its Normal input the mapped normal),
    // bent where needed so that the mirror direction of wo (unit, toward the viewer) stays
    // above the geometric surface (Cycles' ensure_valid_reflection). Call before material_at;
    // does nothing for materials without either. Never throws.
    void shade_normal(SurfaceHit& hit, const Vec3& wo) const;
    // The textured materials (ShapeInfo::textured indexes them).
    std::span<const TexturedMaterial> textured_materials() const { return m_textured; }
    // Texture memory: whole images, and the tile cache of paged ones with its counters so far
    // (texel_image.h, "Memory bound").
    TextureMemoryStats texture_memory() const;

    // Warnings build_scene() reported (dropped zero-area triangles, ...), one line each.
    std::span<const std::string> warnings() const { return m_warnings; }

    // Benchmark peer: traces `rays` with bare Embree calls (rtcIntersect1, or rtcOccluded1 when
    // `shadow`), without building SurfaceHits; returns the number of rays that hit something.
    std::uint64_t trace_raw(std::span<const Ray> rays, bool shadow) const;
    // The same with Embree's 8-wide packets (rtcIntersect8 / rtcOccluded8) over consecutive
    // groups of 8 rays, for comparison: what packet tracing would gain on the same rays.
    std::uint64_t trace_raw_packet(std::span<const Ray> rays, bool shadow) const;

    // Largest coordinate magnitude build_scene accepts (shapes' extents and the camera). Embree's
    // float triangle test forms products of three coordinate differences, which overflow float
    // beyond ~7e12 (a Cornell box scaled by 1e10, coordinates 5.5e12, got hits at t = inf);
    // 1e12 keeps those products below 8e36. Measured: the Cornell box renders the same image
    // (relative MSE < 1e-13) at scales 1e-6 .. 3e9 (coordinates up to 1.7e12).
    static constexpr double kMaxCoordinate = 1e12;

    // Implementation detail (the loader and the Embree wrapper fill these).
    struct Impl;
    struct Builder;

  private:
    friend struct Builder;
    // Any hit with t in (0, r.tmax) (planes outside Embree, then Embree's occlusion query).
    bool occluded_ray(const Ray& r) const;
    // The same at shutter time `time` (motion blur).
    bool occluded_ray_at(const Ray& r, float time) const;
    // Planes, then the hit record, after Embree reported (geom, prim, u, v, t) for `ray` at
    // shutter time `time`; `inst`: the instance's Embree id when the hit is inside an instance
    // (else invalid).
    // kSurfaceExtras: the scene has shape parts or texture coordinates (embree_scene.cpp);
    // without them the hit record skips their look-ups.
    template <bool kSurfaceExtras>
    [[gnu::always_inline]] bool complete_hit(const Ray& ray, float time, unsigned inst,
                                             unsigned geom, unsigned prim, float u, float v,
                                             float t, SurfaceHit& hit) const;
    std::string m_name;
    std::uint64_t m_fingerprint = 0;
    std::vector<std::string> m_warnings;
    Camera m_camera;
    CameraMotion m_camera_motion;
    ShutterCurve m_shutter;
    RenderSettings m_settings;
    SceneFeatures m_features;
    // Stable addresses; shared with the combinations (mix, add) that hold them as children.
    std::vector<std::shared_ptr<Material>> m_materials;
    std::vector<std::unique_ptr<Texture>> m_textures;  // stable addresses
    std::vector<TexturedMaterial> m_textured;
    TextureMemoryStats m_texture_memory;            // as the build left it
    std::shared_ptr<const TileCache> m_tile_cache;  // null while nothing is paged
    std::vector<ShapeInfo> m_shapes;
    std::vector<Light> m_lights;
    LightDistribution m_light_distribution;
    LightDistribution m_view_light_distribution;
    std::vector<std::uint32_t> m_camera_lamps;  // indices of lights with camera_visible()
    std::int32_t m_environment = -1;
    std::vector<Medium> m_media;
    std::int32_t m_world_medium = -1;
    std::vector<MediumInterface> m_interfaces;
    std::vector<LightPathSwitch> m_light_paths;
    std::vector<std::uint8_t> m_light_visibility;
    Bounds3 m_bounds;
    std::unique_ptr<Impl> m_impl;  // geometry + Embree (embree_scene.cpp)
};

// Inline: these run for every continuation and shadow ray.
[[gnu::always_inline]] inline Ray Scene::spawn_ray(const Vec3& p, const Vec3& p_err, const Vec3& ng,
                                                   const Vec3& d) {
    Ray r;
    r.o = offset_ray_origin(p, p_err, ng, d);
    r.d = d;
    r.tmax = kInfinity;
    return r;
}

[[gnu::always_inline]] inline Ray Scene::shadow_ray_from(const Vec3& o, const LightLiSample& ls) {
    Ray r;
    r.o = o;
    if (!std::isfinite(ls.dist)) {
        r.d = ls.wi;
        r.tmax = kInfinity;
        return r;
    }
    const Vec3 q = offset_ray_origin(ls.p_light, ls.p_light_err, ls.n_light, o - ls.p_light);
    const Vec3 d = q - o;
    const float len = std::sqrt(glm::dot(d, d));
    r.d = len > 0.f ? d / len : Vec3(0.f, 0.f, 1.f);
    r.tmax = len * (1.f - kShadowEpsilon);
    return r;
}

// Resource limits the loader enforces (scenes/FORMAT.md); an input over a limit is a SceneError.
// The defaults allow any sensible scene; the fuzzer lowers them and forbids file access.
struct SceneLimits {
    std::uint64_t max_triangles = std::uint64_t(1) << 26;  // 67M triangles in the whole scene
    std::int64_t max_pixels = std::int64_t(1) << 28;
    bool allow_files = true;  // mesh "file" entries and environment map images
    // Bytes of texture texels (float, MIP levels included) the scene may hold, at least
    // kMinTextureMemory (TexelImageCache): images past it are paged through a tile cache
    // within it (texel_image.h, "Memory bound").
    std::uint64_t texture_memory = kDefaultTextureMemory;
};

// Loads a scene file (JSON, scenes/FORMAT.md): read_scene_description() then build_scene()
// (scene_description.h). Throws SceneError("<path>: <pointer>: message"). Relative mesh file
// paths are resolved against the scene file's directory.
Scene load_scene(const std::string& path, const SceneLimits& limits = {});
// Same, from JSON text; `name_for_errors` prefixes messages, `base_dir` resolves mesh files.
Scene load_scene_from_string(const std::string& json, const std::string& name_for_errors,
                             const std::string& base_dir = ".", const SceneLimits& limits = {});

}  // namespace facet::render
