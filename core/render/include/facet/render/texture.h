// Textures as parameter values: an image (read through TexelImageCache), a checker, the vertex
// colour or a procedural pattern (Blender's Noise, Voronoi, ...), evaluated at a hit. A material
// parameter or a shape's emission holds either a constant (the ParamSet / ShapeDesc value) or
// one of these (scenes/FORMAT.md, "Textures").
//
// Structure: one unit per texture kind (core/render/src/textures/<kind>.cpp) defines its
// TextureKindDef (texture_kinds.h: name, parameters, builder) and its TextureSource (the
// evaluation); a Texture is the kind's source with what every kind shares (value range, the
// inputs it reads, the importer's vertex tint). Adding a kind: one unit and its line in the
// table (textures/texture_kinds.cpp).
//
// Conventions:
//  - UV: (0, 0) is the bottom-left corner of the image, v grows upward, [0, 1]^2 covers the
//    image once (the convention of OBJ and Blender). Texel (x, y) of a TexelImage (row 0 at the
//    top) covers u in [x / W, (x + 1) / W] and v in [1 - (y + 1) / H, 1 - y / H]; its centre is
//    ((x + 0.5) / W, 1 - (y + 0.5) / H).
//  - The UV transform maps the hit's uv to the texture's:
//      uv' = R(uv_rotation) (uv_scale * uv) + uv_offset,
//    R rotating counter-clockwise by uv_rotation degrees about (0, 0), `*` per component.
//  - Filters: closest (the texel containing uv'), linear (bilinear between the 4 texel centres
//    around uv'), mipmap (trilinear over the image's MIP levels, texel_image.h; the default).
//    Wrap modes act on texel indices of every level: repeat (period W_l), clamp (edge texels),
//    mirror (period 2 W_l, reflected).
//  - Mipmap level (Williams 1983; pbrt-v4 section 10.4.3, isotropic trilinear): the pixel's
//    footprint in uv (UvFootprint: duv/dx, duv/dy per pixel step, from ray differentials,
//    camera.h) is mapped into level-0 texel units, g = diag(W, H) A duv (A the UV transform's
//    linear part), and the level is lambda = log2(max(|g_x|, |g_y|)), the longer of the two
//    footprint vectors (isotropic: blurrier than anisotropic filtering at grazing angles, never
//    aliased). One pixel spanning exactly 2^k texels gives lambda = k. lambda <= 0
//    (magnification, or a zero footprint) is exactly the bilinear lookup of level 0 (bit for
//    bit the "linear" filter); otherwise the bilinear lookups of levels floor(lambda) and
//    floor(lambda) + 1 are blended linearly in lambda, and lambda past the last (1 x 1) level
//    reads that level.
//  - Values: a colour texture of a 1- or 2-channel image is grey (channel 0 in r, g, b); of a
//    3+ channel image, its first three channels; `channel` picks one channel (or the Rec. 709
//    luminance 0.2126 R + 0.7152 G + 0.0722 B of linear values) as grey. A number texture
//    reads channel 0 of a 1- or 2-channel image and needs `channel` otherwise. Every value is
//    multiplied by `scale` last; a colour `scale` ([r, g, b], `color_scale`) multiplies per
//    channel (a colour parameter's tint, e.g. glTF's baseColorFactor times its texture).
//  - Paged images (texel_pages.h) are looked up through the tile cache with the same
//    arithmetic as whole ones: a texture's values do not depend on the memory bound.
//  - Checker: cell (i, j) = (floor(n u'), floor(n v')), colour colors[(i + j) mod 2]; so the
//    cell at the UV origin has colors[0].
//  - Vertex colour ({"vertex_color": true}): the hit's vertex colour c = (1 - b1 - b2) c0 +
//    b1 c1 + b2 c2 (linear RGBA, barycentric b1, b2; mesh.h), read as an image texel is: its
//    RGB as a colour, or `channel` r, g, b, a or luminance as grey; times `scale`. No UVs, no
//    filtering. Its range is [0, scale] per channel (mesh colours lie in [0, 1]).
//  - Vertex tint (TextureDesc::times_vertex_color, an importer's: glTF's COLOR_0 times its
//    base colour texture): an image or checker value multiplied per channel by c's RGB.
//  - Procedural kinds (textures/procedural.h) read a 3D point: the hit's `coordinates`
//    ("generated", "object", "uv" as (u, v, 0), or the view-dependent "normal", "reflection",
//    "camera", "window": TexturePoint), mapped by the affine `mapping` (Blender's
//    Mapping node and any affine chain before the texture), then the kind's own pattern.
//  - Composite kinds (textures/composite.h: math, vector_math, mix_rgb, color_ramp) read no
//    point: their inputs are constants or other textures (TextureDesc::inputs), evaluated at
//    the same hit; the composite's value is its node's function of theirs.
//  - Hair Info (textures/hair_info.cpp): one of Blender's Hair Info outputs at the hit (Random,
//    Intercept, Is Strand: TexturePoint::strand_random, strand_v, on_strand), 0 off curves.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/mat2x2.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "facet/registry.h"
#include "facet/render/texel_image.h"
#include "facet/types.h"

namespace facet::render {

struct TextureInputDesc;

// One stop of a colour ramp (the color_ramp kind): its position in [0, 1] and its linear RGBA.
struct TextureStop {
    double position = 0.0;
    glm::dvec4 color{0.0, 0.0, 0.0, 1.0};
    bool operator==(const TextureStop&) const = default;
};

// A texture as the scene format writes it (plain data, validated by build_scene).
struct TextureDesc {
    // The kind (texture_kinds.h): "image", "checker", "vertex_color" or a procedural kind's
    // name ("noise", "voronoi", ...).
    std::string kind = "image";
    // An image or checker multiplied by the vertex colour (glTF's COLOR_0 times its base colour
    // texture; an importer's, never read from or written to JSON).
    bool times_vertex_color = false;
    // Image
    std::string file;  // relative to the scene file's directory (a name for `image`)
    // In-memory texels instead of a file (the Python module's numpy arrays, already decoded:
    // texel_image_from_memory); the scene writer cannot write it (an error).
    std::shared_ptr<const TexelImage> image;
    std::string colorspace;  // "" (default: image's), "srgb", "linear"
    std::string filter;      // "" (default: mipmap), "closest", "linear", "mipmap"
    std::string wrap;        // "" (default: repeat), "repeat", "clamp", "mirror"
    std::string channel;     // "" (all), "r", "g", "b", "a", "luminance"
    // An encoded image held in memory instead of a file (an importer's: a .glb's buffer view or
    // a data: URI); `file` then names it ("/path/model.glb#/images/0", with the format's
    // extension appended) for messages and the image cache. Never written to JSON.
    std::shared_ptr<const std::vector<unsigned char>> bytes;
    // Checker
    std::array<Rgb, 2> colors{Rgb(0.f), Rgb(1.f)};
    double checker_scale = 1.0;  // cells per unit of uv'
    // Procedural kinds: the kind's parameters by name (numbers, names), checked against its
    // table (texture_kinds.h); absent ones take the table's defaults.
    ParamSet params;
    // The point a procedural kind reads: "" (the kind's default, "generated"), "generated",
    // "object" or "uv"; and the affine map applied to it (object to texture space, identity by
    // default; JSON "mapping").
    std::string coordinates;
    glm::dmat4 mapping{1.0};
    // Composite kinds: the inputs given as textures, by parameter name (a constant input is a
    // number or colour in `params`); and a colour ramp's stops, in order.
    std::vector<TextureInputDesc> inputs;
    std::vector<TextureStop> stops;
    // Image and checker
    Vec2 uv_scale{1.f}, uv_offset{0.f};
    double uv_rotation = 0.0;  // degrees, counter-clockwise
    // All kinds
    double scale = 1.0;    // multiplier on the value
    Rgb color_scale{1.f};  // per-channel multiplier (JSON "scale": [r, g, b]), times `scale`
    bool operator==(const TextureDesc&) const = default;
};

// A composite kind's input fed by a texture (TextureDesc::inputs).
struct TextureInputDesc {
    std::string name;  // the kind's parameter
    TextureDesc texture;
    bool operator==(const TextureInputDesc&) const = default;
};

enum class TextureFilter : std::uint8_t { Closest, Linear, Mipmap };

// A pixel's footprint in texture coordinates: the change of uv per pixel step along film x
// and along film y (zero: a point, sampled at level 0). From uv_footprint (scene.h).
struct UvFootprint {
    Vec2 duvdx{0.f}, duvdy{0.f};
};

enum class TextureWrap : std::uint8_t { Repeat, Clamp, Mirror };

// Blender's Light Path outputs for the ray that reached a hit, as Cycles 3.4 gives them to a
// surface shader (svm_node_light_path), kept by the kernel that tracks rays' kinds (the media
// kernel; integrator.h "Ray visibility"):
//  - `kinds`: scene.h LightPathRay bits (kLpCamera, ...) of the ray;
//  - `length`: the distance from the ray's origin (the previous vertex or the camera; shapes
//    the ray does not see do not restart it) to the hit;
//  - `depth`: the bounces before the hit that are not straight pass-throughs (transparent
//    samples, `null` crossings); a scattering in a medium counts;
//  - `diffuse`, `glossy`, `transmission`: the diffuse and glossy reflections, and the samples
//    that crossed a surface, among them (Cycles' diffuse_bounce, glossy_bounce,
//    transmission_bounce: a crossing counts as transmission only).
struct RayState {
    float length = 0.f;
    std::uint16_t depth = 0, diffuse = 0, glossy = 0, transmission = 0;
    std::uint8_t kinds = 1u;  // kLpCamera
};

// The last image lookup at a hit: an image's filtered texels (channels `first`.., before a
// texture's channel choice and scale) at transformed coordinates `t` and MIP level `lambda`.
// Textures that read the same image at the same point share it (Scene::textured_material).
struct ImageLookupMemo {
    const void* image = nullptr;  // the TexelImage; null: empty
    const void* mips = nullptr;   // its MIP levels (null: none)
    Vec2 t{0.f};
    float lambda = 0.f;
    int first = 0;
    std::uint8_t filter = 0, wrap = 0;
    float raw[4] = {0.f, 0.f, 0.f, 0.f};
};

// What a texture reads at a hit.
struct TexturePoint {
    Vec2 uv{0.f};                            // the hit's uv (shapes that compute it)
    const UvFootprint* footprint = nullptr;  // the pixel's footprint in uv; null: a point
    glm::vec4 color{1.f};                    // the vertex colour (linear RGBA)
    Vec3 object{0.f};                        // the object-space position
    // The position in the shape's texture space: [0, 1]^3 over its box (Blender's Generated
    // coordinates; ShapeInfo::texture_space).
    Vec3 generated{0.f};
    // Texture Coordinate's view-dependent outputs as Cycles 3.4 defines them (svm_tex_coord),
    // filled only on shapes whose textures read them (kTextureReadsView; ShapeInfo::needs_view):
    //  - normal: the object-space shading normal (unit), turned to the ray's side (Normal);
    //  - reflection: the view direction mirrored about the world-space shading normal,
    //    2 dot(n, wo) n - wo, wo the unit direction toward the viewer (Reflection);
    //  - camera: the position in camera space, x right, y up, z forward (Camera);
    //  - window: the position on the image, (x, y, 0) with [0, 1]^2 from the image's bottom-left
    //    corner to its top-right one (Window; Camera::window_point).
    Vec3 normal{0.f}, reflection{0.f}, camera{0.f}, window{0.f};
    // Blender's Hair Info outputs at a hit on curves (filled only on shapes whose textures read
    // them: kTextureReadsStrand, ShapeInfo::needs_strand; 0 elsewhere, as Cycles gives off
    // curves): `strand_random`, the strand's random value in [0, 1] (Random: scene.h,
    // curve_random); `strand_v`, the position along it (SurfaceHit::strand_v); `on_strand`, 1
    // on curves (Is Strand).
    float strand_random = 0.f, strand_v = 0.f, on_strand = 0.f;
    // The Light Path state of the ray that reached the hit (kTextureReadsRay; null outside the
    // kernel that tracks it: a camera ray's at length 0 is read then).
    const RayState* ray = nullptr;
    // Where image lookups at this point are shared (null: none kept). Valid for one hit: the
    // images it names belong to the scene being rendered.
    ImageLookupMemo* memo = nullptr;
};

// What a texture reads besides its parameters (bits of Texture::inputs()).
enum TextureInput : unsigned {
    kTextureReadsUv = 1u,        // TexturePoint::uv (and footprint)
    kTextureReadsColor = 2u,     // TexturePoint::color
    kTextureReadsPosition = 4u,  // TexturePoint::object and generated
    kTextureReadsView = 8u,      // TexturePoint::normal, reflection, camera and window
    kTextureReadsStrand = 16u,   // TexturePoint::strand_random, strand_v and on_strand
    kTextureReadsRay = 32u,      // TexturePoint::ray (Light Path outputs)
};

// One kind's evaluation (immutable, thread-safe, never throws): the value at a point, times the
// texture's scale.
class TextureSource {
  public:
    virtual ~TextureSource() = default;
    virtual Rgb eval(const TexturePoint& p) const = 0;
    // An image's MIP level for footprint fp (0 for the other kinds), its texels, its filter.
    virtual float mip_level(const UvFootprint&) const { return 0.f; }
    virtual const TexelImage* texel_image() const { return nullptr; }
    virtual TextureFilter filter() const { return TextureFilter::Linear; }
};

// A texture ready to evaluate (immutable, thread-safe). Never throws once built.
class Texture {
  public:
    // `channel`: -1 all (colour) channels, 0..3 one channel, 4 luminance.
    static constexpr int kAllChannels = -1, kLuminance = 4;
    // A kind's source, its value range per channel (every value lies in [min, max]), the
    // inputs it reads (TextureInput bits) and whether its value is tinted by the vertex colour
    // (TextureDesc::times_vertex_color; then kTextureReadsColor is added).
    Texture(std::shared_ptr<const TextureSource> source, Rgb min, Rgb max, unsigned inputs,
            bool tint = false);
    // The built-in kinds' constructors (their units: textures/image.cpp, checker.cpp,
    // vertex_color.cpp). `mips`: the image's MIP levels 1, 2, ... (TexelImageCache::
    // mip_levels), needed by the Mipmap filter only (null otherwise).
    static Texture image(std::shared_ptr<const TexelImage> img, TextureFilter filter,
                         TextureWrap wrap, int channel, const TextureDesc& transform,
                         std::shared_ptr<const std::vector<TexelImage>> mips = nullptr);
    static Texture checker(const TextureDesc& desc);
    // The vertex colour (conventions); `channel` as for images.
    static Texture vertex_color(const TextureDesc& desc, int channel);

    // The value at point p (see conventions): a colour (grey for one channel).
    Rgb eval(const TexturePoint& p) const {
        const Rgb v = m_source->eval(p);
        return m_tint ? v * Rgb(p.color) : v;
    }
    // The value at uv alone (no footprint: the Mipmap filter reads level 0; vertex colour
    // white, positions 0).
    Rgb eval(Vec2 uv) const { return eval(TexturePoint{uv}); }
    // The value at uv filtered over the pixel footprint `fp` (Mipmap; the other kinds ignore
    // fp).
    Rgb eval(Vec2 uv, const UvFootprint& fp) const { return eval(TexturePoint{uv, &fp}); }
    // The value at a hit with uv, footprint fp and interpolated vertex colour `color` (linear
    // RGBA; (1, 1, 1, 1) on surfaces without colours).
    Rgb eval(Vec2 uv, const UvFootprint& fp, const glm::vec4& color) const {
        return eval(TexturePoint{uv, &fp, color});
    }
    // What the value depends on (TextureInput bits).
    unsigned inputs() const { return m_inputs; }
    bool uses_uv() const { return (m_inputs & kTextureReadsUv) != 0; }
    bool uses_vertex_color() const { return (m_inputs & kTextureReadsColor) != 0; }
    bool uses_position() const { return (m_inputs & kTextureReadsPosition) != 0; }
    bool uses_view() const { return (m_inputs & kTextureReadsView) != 0; }
    bool uses_strand() const { return (m_inputs & kTextureReadsStrand) != 0; }
    bool uses_ray() const { return (m_inputs & kTextureReadsRay) != 0; }
    // The (continuous) MIP level of footprint fp (conventions), before clamping to the levels.
    float mip_level(const UvFootprint& fp) const { return m_source->mip_level(fp); }
    TextureFilter filter() const { return m_source->filter(); }
    // Smallest and largest value per channel over the whole texture (every texel, times scale;
    // bilinear values lie between them), for validation against a parameter's range.
    Rgb min_value() const { return m_min; }
    Rgb max_value() const { return m_max; }
    // The image (null for the other kinds).
    const TexelImage* texel_image() const { return m_source->texel_image(); }
    const TextureSource& source() const { return *m_source; }

  private:
    std::shared_ptr<const TextureSource> m_source;
    Rgb m_min{0.f}, m_max{0.f};
    unsigned m_inputs = 0;
    bool m_tint = false;
};

// The affine map uv' = A uv + b of a UV transform (conventions): A = R(uv_rotation)
// diag(uv_scale), b = uv_offset.
void uv_transform(const TextureDesc& d, glm::mat2& a, Vec2& b);

// Blender's Mapping node of type Point as an affine map: p' = T(location) R diag(scale) p, with
// R = Rz Ry Rx of the Euler angles `rotation` (radians; Cycles' euler_to_transform).
glm::dmat4 mapping_point_matrix(const glm::dvec3& location, const glm::dvec3& rotation,
                                const glm::dvec3& scale);

// Wraps texel index i into [0, n) by `wrap` (conventions); indices inside are themselves.
int wrap_index_outside(int i, int n, TextureWrap wrap);
inline int wrap_index(int i, int n, TextureWrap wrap) {
    return unsigned(i) < unsigned(n) ? i : wrap_index_outside(i, n, wrap);
}

}  // namespace facet::render
