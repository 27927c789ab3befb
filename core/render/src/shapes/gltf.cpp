// Shape kind "gltf": every triangle primitive of a glTF 2.0 file (.gltf or .glb, read by
// tinygltf), with its node transforms and its metallic-roughness material; and the scene that
// `facet render model.glb` renders (facet/render/gltf.h).
//
// Conventions (docs/gltf.md):
//  - Axes: glTF is right-handed, Y up, metres. The import turns it Z-up as Blender's glTF
//    importer does, (x, y, z)_glTF -> (x, -z, y) (a rotation of +90 degrees about x, so no
//    winding changes), then applies the shape's "transform".
//  - Which nodes: the default scene's ("scene"), else scene 0, else (a file without scenes)
//    every root node, with a warning. Node transforms compose parent * child; a node's local
//    transform is its "matrix" or T * R * S.
//  - Materials: base colour b, metallic m, roughness r -> composite with
//    diffuse_reflectance = b (1 - m), a GGX lobe of alpha = r^2, Schlick Fresnel with
//    f0 = 0.04 (1 - m) + b m (glTF 2.0 spec, Appendix B: F0 = mix(0.04, b, m));
//    emission = emissiveFactor x KHR_materials_emissive_strength (radiance);
//    two_sided = doubleSided (and the shape's "two_sided").
//  - Textures (docs/gltf.md): TEXCOORD_0 as the mesh's uvs, v -> 1 - v; base colour, metallic-
//    roughness and emissive textures times their factors, with their samplers and
//    KHR_texture_transform; images from files, .glb buffer views and data: URIs (decoded from
//    memory by the texture layer); alphaMode MASK / BLEND as the material's opacity.
//  - Vertex colours: COLOR_0 multiplies the base colour (glTF 3.9.2).
//  - Nothing is dropped silently: what is not converted (occlusion textures, other UV and
//    colour sets, skins, morph targets, animations, cameras, lights, extensions) is reported
//    once per material or extension as "<file>#<glTF JSON pointer>: ...", a warning of the
//    build; bad data and unknown required extensions are errors of the same form.
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#include <tiny_gltf.h>

#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>

#include "../io/pov_writer.h"
#include "../kind_build.h"
#include "facet/render/gltf.h"

namespace facet::render {

namespace {

// glTF Y-up -> Facet Z-up: (x, y, z) -> (x, -z, y). Columns of the matrix (glm layout).
const glm::dmat4 kYUpToZUp(glm::dvec4(1, 0, 0, 0), glm::dvec4(0, 0, 1, 0), glm::dvec4(0, -1, 0, 0),
                           glm::dvec4(0, 0, 0, 1));

// The dielectric reflectance at normal incidence of glTF's reference BRDF (IOR 1.5).
constexpr double kDielectricF0 = 0.04;

// Node hierarchies deeper than this are rejected (glTF nodes form trees; a deeper one is
// almost certainly broken, and the traversal keeps a stack of this size at most).
constexpr std::size_t kMaxNodeDepth = 1024;

std::string idx(std::size_t i) {
    return std::to_string(i);
}

// tinygltf decodes no image for us: Facet's own image reader (texel_image.h) decodes textures.
// The encoded bytes tinygltf hands over (from a buffer view, a data: URI, or a file whose URI
// is percent-encoded) are kept per image index; other files are read by their path
// (is_file_uri), through the scene's image cache.
using ImageBytes = std::map<int, std::shared_ptr<const std::vector<unsigned char>>>;
bool is_file_uri(const std::string& uri) {
    return !uri.empty() && uri.rfind("data:", 0) != 0 && uri.find('%') == std::string::npos;
}
bool keep_image(tinygltf::Image* image, const int index, std::string*, std::string*, int, int,
                const unsigned char* bytes, int size, void* user) {
    if (bytes && size > 0 && !is_file_uri(image->uri))
        (*static_cast<ImageBytes*>(user))[index] =
            std::make_shared<const std::vector<unsigned char>>(bytes, bytes + size);
    return true;
}

// The format of an encoded image by its signature, as a file extension for the reader (which
// picks its decoder by extension): PNG, JPEG, else none.
std::string image_extension(const std::vector<unsigned char>& b, const std::string& mime) {
    if (b.size() >= 8 && b[0] == 0x89 && b[1] == 'P' && b[2] == 'N' && b[3] == 'G') return ".png";
    if (b.size() >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF) return ".jpg";
    if (mime == "image/png") return ".png";
    if (mime == "image/jpeg") return ".jpg";
    return "";
}

// glTF sampler constants (glTF 2.0, 5.26).
constexpr int kNearest = 9728, kClampToEdge = 33071, kMirroredRepeat = 33648;

const char* wrap_name(int w) {
    return w == kClampToEdge ? "clamp" : w == kMirroredRepeat ? "mirror" : "repeat";
}

// The glTF texture sources of gltf_composite_params: what a texture may replace.
const MaterialConversion kGltfConversion{{{"base_color", ParamType::Color, "1", "baseColor"},
                                          {"metallic", ParamType::Number, "1", "metallic"},
                                          {"roughness", ParamType::Number, "1", "roughness"}},
                                         gltf_composite_params,
                                         {"diffuse_reflectance", "alpha", "f0"},
                                         gltf_composite_values};

const char* type_name(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR:
            return "SCALAR";
        case TINYGLTF_TYPE_VEC2:
            return "VEC2";
        case TINYGLTF_TYPE_VEC3:
            return "VEC3";
        case TINYGLTF_TYPE_VEC4:
            return "VEC4";
        case TINYGLTF_TYPE_MAT2:
            return "MAT2";
        case TINYGLTF_TYPE_MAT3:
            return "MAT3";
        case TINYGLTF_TYPE_MAT4:
            return "MAT4";
    }
    return "unknown";
}

const char* component_name(int c) {
    switch (c) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
            return "BYTE (5120)";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return "UNSIGNED_BYTE (5121)";
        case TINYGLTF_COMPONENT_TYPE_SHORT:
            return "SHORT (5122)";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return "UNSIGNED_SHORT (5123)";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
            return "UNSIGNED_INT (5125)";
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
            return "FLOAT (5126)";
    }
    return "an unknown component type";
}

// Reads one glTF file into object-space parts, materials and reports.
class Importer {
  public:
    explicit Importer(std::string path, bool share_meshes = false)
        : m_path(std::move(path)),
          m_file(std::filesystem::path(m_path).filename().string()),
          m_share(share_meshes) {}
    // From bytes in memory (the fuzzer), named `name`; external files are refused.
    Importer(std::string_view bytes, std::string name)
        : m_file(std::move(name)), m_memory(bytes), m_in_memory(true) {}

    GltfImport run() {
        load();
        check_extensions();
        report_unconverted_file_features();
        m_out.num_cameras = m_model.cameras.size();
        m_out.materials.resize(m_model.materials.size());
        for (std::size_t i = 0; i < m_model.materials.size(); ++i) {
            m_out.materials[i] = convert_material(m_model.materials[i], "/materials/" + idx(i));
        }
        if (m_share) {
            m_uses.assign(m_model.meshes.size(), 0);
            for (const tinygltf::Node& nd : m_model.nodes)
                if (nd.mesh >= 0 && std::size_t(nd.mesh) < m_uses.size())
                    ++m_uses[std::size_t(nd.mesh)];
        }
        for (int root : roots()) traverse(root);
        return std::move(m_out);
    }

  private:
    [[noreturn]] void fail(const std::string& pointer, const std::string& message) const {
        throw std::runtime_error(m_file + "#" + pointer + ": " + message);
    }
    // The file's `array[index]`, or an error at `ptr` naming the missing element.
    template <class T>
    const T& element(const std::vector<T>& array, int index, const std::string& ptr,
                     const char* what) const {
        if (index < 0 || std::size_t(index) >= array.size()) {
            fail(ptr, std::string(what) + " " + std::to_string(index) +
                          " does not exist (the file has " + idx(array.size()) + ")");
        }
        return array[std::size_t(index)];
    }
    // Reported once per `key` (an extension, a material's texture slot, an attribute name).
    void report(const std::string& key, const std::string& pointer, const std::string& message) {
        if (m_reported.insert(key).second) {
            m_out.reports.push_back(m_file + "#" + pointer + ": " + message);
        }
    }

    void load() {
        tinygltf::TinyGLTF loader;
        loader.SetImageLoader(keep_image, &m_image_bytes);
        std::string err, warn;
        if (m_in_memory) return load_memory(loader);
        std::string ext = std::filesystem::path(m_path).extension().string();
        for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
        if (ext != ".gltf" && ext != ".glb") {
            throw std::runtime_error(m_file + ": unsupported glTF file extension '" + ext +
                                     "' (use .gltf or .glb)");
        }
        if (!std::filesystem::is_regular_file(m_path)) {
            throw std::runtime_error(m_file + ": cannot open '" + m_path + "'");
        }
        const bool ok = ext == ".glb" ? loader.LoadBinaryFromFile(&m_model, &err, &warn, m_path)
                                      : loader.LoadASCIIFromFile(&m_model, &err, &warn, m_path);
        if (!ok && ext == ".gltf") {
            // tinygltf fails on Draco-only accessors before its caller sees the required
            // extensions: name them first when the JSON of a .gltf lists them.
            std::ifstream in(m_path);
            check_required_in_json(std::string(std::istreambuf_iterator<char>(in), {}));
        }
        loaded(ok, err, warn);
    }

    // tinygltf's filesystem for bytes in memory: no file exists, none can be read.
    static bool no_file(const std::string&, void*) { return false; }
    static std::string same_path(const std::string& p, void*) { return p; }
    static bool no_read(std::vector<unsigned char>*, std::string* err, const std::string& p,
                        void*) {
        if (err) *err += "external file '" + p + "' refused (reading from memory)\n";
        return false;
    }
    static bool no_write(std::string*, const std::string&, const std::vector<unsigned char>&,
                         void*) {
        return false;
    }

    void load_memory(tinygltf::TinyGLTF& loader) {
        loader.SetFsCallbacks({no_file, same_path, no_read, no_write, nullptr});
        std::string err, warn;
        const auto* bytes = reinterpret_cast<const unsigned char*>(m_memory.data());
        const auto n = unsigned(std::min<std::size_t>(m_memory.size(), 1u << 30));
        const bool binary = m_memory.substr(0, 4) == "glTF";
        const bool ok =
            binary ? loader.LoadBinaryFromMemory(&m_model, &err, &warn, bytes, n, "")
                   : loader.LoadASCIIFromString(&m_model, &err, &warn, m_memory.data(), n, "");
        if (!ok && !binary) check_required_in_json(std::string(m_memory));
        loaded(ok, err, warn);
    }

    void loaded(bool ok, std::string& err, const std::string& warn) {
        if (!ok) {
            while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
            throw std::runtime_error(m_file + ": not a readable glTF 2.0 file: " +
                                     (err.empty() ? std::string("tinygltf failed") : err));
        }
        // tinygltf's warnings (e.g. a missing image file) are not errors for geometry: pass them
        // on.
        std::size_t start = 0;
        while (start < warn.size()) {
            std::size_t end = warn.find('\n', start);
            if (end == std::string::npos) end = warn.size();
            if (end > start)
                m_out.reports.push_back(m_file + ": " + warn.substr(start, end - start));
            start = end + 1;
        }
    }

    // The top-level "extensionsRequired" of a .gltf that tinygltf could not load (nlohmann's
    // JSON reader; any failure leaves tinygltf's own message to be reported).
    void check_required_in_json(const std::string& text) {
        const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
        if (!j.is_object() || !j.contains("extensionsRequired")) return;
        const nlohmann::json& r = j["extensionsRequired"];
        if (!r.is_array()) return;
        for (const nlohmann::json& e : r) {
            if (e.is_string()) m_model.extensionsRequired.push_back(e.get<std::string>());
        }
        check_required();
    }

    // Required extensions Facet cannot honour are errors; used ones it does not convert are
    // reported.
    void check_extensions() {
        check_required();
        for (std::size_t i = 0; i < m_model.extensionsUsed.size(); ++i) {
            const std::string& e = m_model.extensionsUsed[i];
            if (converted_extension(e)) continue;
            report("ext:" + e, "/extensionsUsed/" + idx(i),
                   "extension '" + e + "' is not converted (the data it extends is used as is)");
        }
    }

    static bool converted_extension(const std::string& e) {
        return e == "KHR_materials_emissive_strength" || e == "KHR_texture_transform";
    }

    void check_required() const {
        for (std::size_t i = 0; i < m_model.extensionsRequired.size(); ++i) {
            const std::string& e = m_model.extensionsRequired[i];
            if (converted_extension(e)) continue;
            std::string why = e == "KHR_draco_mesh_compression"
                                  ? "Draco-compressed meshes cannot be read (tinygltf is built "
                                    "without Draco); re-export the file uncompressed"
                                  : "the extension is required by the file and Facet does not "
                                    "support it";
            fail("/extensionsRequired/" + idx(i), "'" + e + "': " + why);
        }
    }

    void report_unconverted_file_features() {
        if (!m_model.skins.empty()) {
            report("skins", "/skins", "skins are not applied (the meshes are imported unposed)");
        }
        if (!m_model.animations.empty()) {
            report("animations", "/animations",
                   "animations are not played (the file's static pose is imported)");
        }
        if (!m_model.lights.empty()) {
            report("lights", "/extensions/KHR_lights_punctual/lights",
                   std::to_string(m_model.lights.size()) +
                       " KHR_lights_punctual light(s) are not converted");
        }
    }

    // --- materials ---------------------------------------------------------------------------

    double unit_number(double v, const std::string& ptr) const {
        if (!std::isfinite(v) || v < 0.0 || v > 1.0) fail(ptr, "must be a number in [0, 1]");
        return v;
    }

    // A texture slot Facet does not use (occlusion): reported, never silently dropped.
    void unused_texture(const std::string& ptr, int index, const std::string& what) {
        if (index < 0) return;
        report(ptr, ptr, "texture " + std::to_string(index) + " (" + what + ") is not used");
    }

    // The image of texture `index` as a TextureDesc (file or encoded bytes, sampler,
    // KHR_texture_transform), or none with a report (then the factor alone is used).
    std::optional<TextureDesc> texture(const std::string& ptr, int index, int tex_coord,
                                       const tinygltf::ExtensionMap& ext, const std::string& what) {
        if (index < 0) return std::nullopt;
        const tinygltf::Texture& t = element(m_model.textures, index, ptr + "/index", "texture");
        const std::string tp = "/textures/" + idx(std::size_t(index));
        TextureDesc d;
        if (auto tt = ext.find("KHR_texture_transform"); tt != ext.end()) {
            const std::string xp = ptr + "/extensions/KHR_texture_transform";
            const tinygltf::Value& v = tt->second;
            if (!v.IsObject()) fail(xp, "expected an object");
            auto pair = [&](const char* key, Vec2 def) {
                const tinygltf::Value& a = v.Get(key);
                if (!a.IsArray()) return def;
                if (a.ArrayLen() != 2) fail(xp + "/" + key, "expected 2 numbers");
                Vec2 out;
                for (int i = 0; i < 2; ++i) {
                    const double x = a.Get(i).GetNumberAsDouble();
                    if (!std::isfinite(x)) fail(xp + "/" + key + "/" + idx(i), "must be finite");
                    out[i] = float(x);
                }
                return out;
            };
            const double rotation = v.Get("rotation").IsNumber() || v.Get("rotation").IsInt()
                                        ? v.Get("rotation").GetNumberAsDouble()
                                        : 0.0;
            if (!std::isfinite(rotation)) fail(xp + "/rotation", "must be finite");
            apply_khr_texture_transform(d, pair("offset", Vec2(0.f)), rotation,
                                        pair("scale", Vec2(1.f)));
            if (v.Get("texCoord").IsInt()) tex_coord = v.Get("texCoord").GetNumberAsInt();
        }
        if (tex_coord != 0) {
            report(ptr + "/texCoord", ptr + "/texCoord",
                   "TEXCOORD_" + std::to_string(tex_coord) +
                       " is not imported (only TEXCOORD_0): "
                       "the " +
                       what + " texture is not used, its factor alone is");
            return std::nullopt;
        }
        if (t.source < 0) {
            report(tp, tp,
                   "the texture has no PNG/JPEG source (an extension's image?): the " + what +
                       " texture is not used, its factor alone is");
            return std::nullopt;
        }
        const std::string ip = "/images/" + idx(std::size_t(t.source));
        const tinygltf::Image& im = element(m_model.images, t.source, tp + "/source", "image");
        if (is_file_uri(im.uri)) {
            if (m_in_memory) {
                report(ip, ip + "/uri",
                       "external image files are refused (reading from memory): the " + what +
                           " texture is not used, its factor alone is");
                return std::nullopt;
            }
            // A file beside the glTF file (URIs are relative to it).
            d.file = (std::filesystem::path(m_path).parent_path() / im.uri).string();
        } else {
            const auto it = m_image_bytes.find(t.source);
            if (it == m_image_bytes.end()) fail(ip, "the image's data are missing or empty");
            const std::string e = image_extension(*it->second, im.mimeType);
            if (e.empty()) fail(ip, "not a PNG or JPEG image (mimeType '" + im.mimeType + "')");
            d.bytes = it->second;
            d.file = (m_in_memory ? m_file : m_path) + "#" + ip + e;
        }
        if (t.sampler >= 0) {
            const tinygltf::Sampler& sa =
                element(m_model.samplers, t.sampler, tp + "/sampler", "sampler");
            const std::string sp = "/samplers/" + idx(std::size_t(t.sampler));
            d.wrap = wrap_name(sa.wrapS);
            if (sa.wrapT != sa.wrapS) {
                report(sp + "/wrapT", sp + "/wrapT",
                       std::string("wrapT differs from wrapS: both use wrapS's ") + d.wrap +
                           " (Facet has one wrap mode per texture)");
            }
            d.filter = sa.magFilter == kNearest ? "closest" : "linear";
            if (sa.minFilter >= 0 && sa.minFilter != sa.magFilter) {
                report(sp + "/minFilter", sp + "/minFilter",
                       "minFilter " + std::to_string(sa.minFilter) +
                           " is not converted: "
                           "minification uses the magFilter's " +
                           d.filter + " filter");
            }
        }
        return d;
    }

    GltfMaterial convert_material(const tinygltf::Material& m, const std::string& ptr) {
        const tinygltf::PbrMetallicRoughness& pbr = m.pbrMetallicRoughness;
        const std::string pp = ptr + "/pbrMetallicRoughness";
        if (pbr.baseColorFactor.size() != 4) {
            fail(pp + "/baseColorFactor", "expected 4 numbers (r, g, b, a)");
        }
        Rgb base;
        for (int c = 0; c < 3; ++c) {
            base[c] = float(unit_number(pbr.baseColorFactor[std::size_t(c)],
                                        pp + "/baseColorFactor/" + idx(std::size_t(c))));
        }
        const double alpha = unit_number(pbr.baseColorFactor[3], pp + "/baseColorFactor/3");
        const double metal = unit_number(pbr.metallicFactor, pp + "/metallicFactor");
        const double rough = unit_number(pbr.roughnessFactor, pp + "/roughnessFactor");
        GltfMaterial out;
        out.pointer = ptr;
        out.name = m.name;
        out.double_sided = m.doubleSided;
        out.desc.model = "composite";
        // Each source: its texture times its factor, or the factor (gltf_composite_params).
        const std::optional<TextureDesc> base_tex =
            texture(pp + "/baseColorTexture", pbr.baseColorTexture.index,
                    pbr.baseColorTexture.texCoord, pbr.baseColorTexture.extensions, "base colour");
        if (base_tex) {
            TextureDesc d = *base_tex;
            d.color_scale = base;  // sRGB-decoded by default (8/16-bit), as glTF's base colour
            out.desc.textures["base_color"] = d;
        } else {
            out.desc.params.set("base_color", base);
        }
        const std::optional<TextureDesc> mr_tex =
            texture(pp + "/metallicRoughnessTexture", pbr.metallicRoughnessTexture.index,
                    pbr.metallicRoughnessTexture.texCoord, pbr.metallicRoughnessTexture.extensions,
                    "metallic-roughness");
        if (mr_tex) {
            // Linear data: metallic in B, roughness in G (glTF 3.9.2).
            TextureDesc d = *mr_tex;
            d.colorspace = "linear";
            d.channel = "b";
            d.scale = metal;
            out.desc.textures["metallic"] = d;
            d.channel = "g";
            d.scale = rough;
            out.desc.textures["roughness"] = d;
        } else {
            out.desc.params.set("metallic", metal);
            out.desc.params.set("roughness", rough);
        }
        // alphaMode: the base colour's alpha (factor times the texture's A) as opacity, cut at
        // alphaCutoff for MASK, stochastic for BLEND (its expectation is the blend).
        if (m.alphaMode == "MASK" || m.alphaMode == "BLEND") {
            if (base_tex) {
                TextureDesc d = *base_tex;
                d.channel = "a";  // an image without alpha is opaque (FORMAT.md, "Opacity")
                d.colorspace = "linear";
                d.scale = alpha;
                out.desc.textures["opacity"] = d;
            } else {
                out.desc.params.set("opacity", alpha);
            }
            if (m.alphaMode == "MASK") {
                if (!std::isfinite(m.alphaCutoff) || !(m.alphaCutoff > 0.0) || m.alphaCutoff > 1.0)
                    fail(ptr + "/alphaCutoff", "must be a number in (0, 1]");
                out.desc.params.set("alpha_cutoff", m.alphaCutoff);
            }
        } else if (m.alphaMode != "OPAQUE") {
            fail(ptr + "/alphaMode", "unknown alphaMode '" + m.alphaMode + "'");
        }

        // tinygltf leaves the array empty when the file omits it (default [0, 0, 0]).
        std::vector<double> emissive = m.emissiveFactor;
        if (emissive.empty()) emissive.assign(3, 0.0);
        if (emissive.size() != 3) fail(ptr + "/emissiveFactor", "expected 3 numbers");
        double strength = 1.0;
        if (auto e = m.extensions.find("KHR_materials_emissive_strength");
            e != m.extensions.end()) {
            const std::string sp = ptr + "/extensions/KHR_materials_emissive_strength";
            const tinygltf::Value& s = e->second.Get("emissiveStrength");
            if (s.IsNumber() || s.IsInt()) {
                strength = s.GetNumberAsDouble();
                if (!std::isfinite(strength) || strength < 0.0) {
                    fail(sp + "/emissiveStrength", "must be a finite number >= 0");
                }
            }
        }
        for (int c = 0; c < 3; ++c) {
            out.emission[c] =
                float(unit_number(emissive[std::size_t(c)], ptr + "/emissiveFactor/" + idx(c)) *
                      strength);
        }
        if (!is_finite(out.emission)) fail(ptr + "/emissiveFactor", "emission overflows float");
        if (auto e = texture(ptr + "/emissiveTexture", m.emissiveTexture.index,
                             m.emissiveTexture.texCoord, m.emissiveTexture.extensions, "emissive");
            e && max_component(out.emission) > 0.f) {
            // Radiance = texture x emissiveFactor x strength (an unset factor, 0, emits nothing).
            out.emission_texture = *e;
            out.emission_texture->color_scale = out.emission;
            out.emission = Rgb(0.f);
        }
        unused_texture(ptr + "/occlusionTexture", m.occlusionTexture.index,
                       "ambient occlusion: Facet computes occlusion itself");
        // Normal map (glTF 3.9.3): tangent space, +Y up, linear; scale multiplies the sampled
        // x and y (scenes/FORMAT.md, "Normal maps": xy_scale). Tangents: the primitive's
        // TANGENT, else MikkTSpace's, as the spec asks.
        if (auto n = texture(ptr + "/normalTexture", m.normalTexture.index,
                             m.normalTexture.texCoord, m.normalTexture.extensions, "normal")) {
            if (!std::isfinite(m.normalTexture.scale))
                fail(ptr + "/normalTexture/scale", "must be a finite number");
            MaterialDesc::NormalMap nm;
            nm.texture = *n;
            nm.texture.colorspace = "linear";
            nm.xy_scale = m.normalTexture.scale;
            out.desc.normal_map = nm;
        }
        for (const auto& [name, _] : m.extensions) {
            if (name == "KHR_materials_emissive_strength") continue;
            report(ptr + "/extensions/" + name, ptr + "/extensions/" + name,
                   "extension '" + name + "' is not converted");
        }
        return out;
    }

    // The glTF default material (spec 3.9.6: white, metallic 1, roughness 1), for primitives
    // without one.
    int default_material(const std::string& prim_ptr) {
        report("default-material", prim_ptr + "/material",
               "no material: glTF's default (base colour 1, metallic 1, roughness 1) is used");
        if (m_default < 0) {
            m_default = int(m_out.materials.size());
            m_out.materials.push_back(convert_material(tinygltf::Material(), prim_ptr));
            m_out.materials.back().pointer = "(glTF default material)";
        }
        return m_default;
    }

    // --- nodes -------------------------------------------------------------------------------

    std::vector<int> roots() {
        const std::size_t n = m_model.nodes.size();
        if (m_model.scenes.empty() && m_model.defaultScene >= 0) {
            fail("/scene", "scene " + std::to_string(m_model.defaultScene) +
                               " does not exist (the file has no scenes)");
        }
        if (!m_model.scenes.empty()) {
            const int s = std::max(m_model.defaultScene, 0);
            const std::string sp = "/scenes/" + std::to_string(s);
            const std::vector<int>& r = element(m_model.scenes, s, "/scene", "scene").nodes;
            for (std::size_t j = 0; j < r.size(); ++j) {
                element(m_model.nodes, r[j], sp + "/nodes/" + idx(j), "node");
            }
            return r;
        }
        // No scene: every node that is no other node's child.
        std::vector<bool> child(n, false);
        for (const tinygltf::Node& nd : m_model.nodes) {
            for (int c : nd.children) {
                if (c >= 0 && std::size_t(c) < n) child[std::size_t(c)] = true;
            }
        }
        std::vector<int> r;
        for (std::size_t i = 0; i < n; ++i) {
            if (!child[i]) r.push_back(int(i));
        }
        report("no-scene", "/scenes",
               "the file has no scene: importing all " + idx(r.size()) + " root node(s)");
        return r;
    }

    glm::dmat4 local_matrix(const tinygltf::Node& nd, const std::string& ptr) const {
        auto finite = [&](const std::vector<double>& v, std::size_t size, const char* key) {
            if (v.empty()) return false;
            if (v.size() != size) fail(ptr + "/" + key, "expected " + idx(size) + " numbers");
            for (std::size_t i = 0; i < size; ++i) {
                if (!std::isfinite(v[i])) fail(ptr + "/" + key + "/" + idx(i), "must be finite");
            }
            return true;
        };
        if (finite(nd.matrix, 16, "matrix")) return glm::make_mat4(nd.matrix.data());
        glm::dmat4 m(1.0);
        if (finite(nd.translation, 3, "translation")) {
            m = glm::translate(m,
                               glm::dvec3(nd.translation[0], nd.translation[1], nd.translation[2]));
        }
        if (finite(nd.rotation, 4, "rotation")) {
            // glTF stores (x, y, z, w); glm's constructor takes (w, x, y, z).
            glm::dquat q(nd.rotation[3], nd.rotation[0], nd.rotation[1], nd.rotation[2]);
            const double len = glm::length(q);
            if (!(len > 0.0)) fail(ptr + "/rotation", "must be a unit quaternion, got length 0");
            m = m * glm::mat4_cast(q / len);
        }
        if (finite(nd.scale, 3, "scale")) {
            m = glm::scale(m, glm::dvec3(nd.scale[0], nd.scale[1], nd.scale[2]));
        }
        return m;
    }

    // Depth-first over the tree under `root`, with an explicit stack (no recursion), refusing
    // cycles and shared children (glTF's nodes form disjoint trees).
    void traverse(int root) {
        struct Item {
            int node;
            glm::dmat4 parent;
            std::string ptr;  // the reference to this node ("/nodes/3/children/0")
            std::size_t depth;
        };
        std::vector<Item> stack{{root, kYUpToZUp, "/nodes/" + std::to_string(root), 0}};
        m_seen.resize(m_model.nodes.size(), false);
        while (!stack.empty()) {
            Item it = std::move(stack.back());
            stack.pop_back();
            const std::size_t ni = std::size_t(it.node);
            const std::string np = "/nodes/" + idx(ni);
            if (m_seen[ni]) {
                fail(it.ptr, "node " + idx(ni) +
                                 " is reached twice (a cycle or a shared child: glTF nodes must "
                                 "form trees)");
            }
            if (it.depth > kMaxNodeDepth) {
                fail(it.ptr, "the node hierarchy is deeper than " + idx(kMaxNodeDepth));
            }
            m_seen[ni] = true;
            const tinygltf::Node& nd = m_model.nodes[ni];
            const glm::dmat4 world = it.parent * local_matrix(nd, np);
            if (nd.camera >= 0) camera(nd, world, np);
            if (nd.skin >= 0) report("skins", np + "/skin", "skins are not applied");
            if (nd.mesh >= 0) mesh(nd.mesh, world, np);
            for (std::size_t j = nd.children.size(); j-- > 0;) {
                const int c = nd.children[j];
                const std::string cp = np + "/children/" + idx(j);
                element(m_model.nodes, c, cp, "node");
                stack.push_back({c, world, cp, it.depth + 1});
            }
        }
    }

    void camera(const tinygltf::Node& nd, const glm::dmat4& world, const std::string& np) {
        const tinygltf::Camera& c = element(m_model.cameras, nd.camera, np + "/camera", "camera");
        const std::string cp = "/cameras/" + std::to_string(nd.camera);
        if (m_out.camera) return;  // the first camera in traversal order is the one used
        if (c.type != "perspective") {
            report("camera-type", cp,
                   "camera type '" + c.type + "' is not converted (only perspective)");
            return;
        }
        GltfCamera cam;
        cam.pointer = cp;
        // The camera looks down its local -z with +y up (glTF 3.10.1), in the node's frame.
        const glm::dvec3 o(world * glm::dvec4(0, 0, 0, 1));
        cam.position = o;
        cam.forward = glm::dvec3(world * glm::dvec4(0, 0, -1, 0));
        cam.up = glm::dvec3(world * glm::dvec4(0, 1, 0, 0));
        const double yfov = c.perspective.yfov;
        if (!(yfov > 0.0 && yfov < M_PI) || !std::isfinite(yfov)) {
            fail(cp + "/perspective/yfov", "must be in (0, pi) radians");
        }
        cam.yfov_deg = yfov * 180.0 / M_PI;
        const double a = c.perspective.aspectRatio;
        if (a > 0.0 && std::isfinite(a)) cam.aspect = a;
        m_out.camera = cam;
    }

    // --- meshes ------------------------------------------------------------------------------

    // A checked view of an accessor's elements.
    struct Elements {
        const unsigned char* data = nullptr;
        std::size_t stride = 0, count = 0;
        int component = 0;
        int type = 0;  // TINYGLTF_TYPE_*
    };

    Elements accessor(int index, const std::string& user, std::initializer_list<int> types,
                      std::initializer_list<int> components) const {
        const tinygltf::Accessor& a = element(m_model.accessors, index, user, "accessor");
        const std::string ap = "/accessors/" + std::to_string(index);
        const std::string used = " (used by " + user + ")";
        if (std::find(types.begin(), types.end(), a.type) == types.end()) {
            std::string want;
            for (int t : types) want += std::string(want.empty() ? "" : " or ") + type_name(t);
            fail(ap + "/type", "expected " + want + ", got " + type_name(a.type) + used);
        }
        if (std::find(components.begin(), components.end(), a.componentType) == components.end()) {
            std::string want;
            for (int c : components) {
                want += std::string(want.empty() ? "" : " or ") + component_name(c);
            }
            fail(ap + "/componentType",
                 "expected " + want + ", got " + component_name(a.componentType) + used);
        }
        if (a.sparse.isSparse) fail(ap + "/sparse", "sparse accessors are not supported" + used);
        if (a.bufferView < 0) {
            fail(ap,
                 "has no bufferView (Draco-compressed or all-zero data are not supported)" + used);
        }
        const tinygltf::BufferView& v =
            element(m_model.bufferViews, a.bufferView, ap + "/bufferView", "buffer view");
        const std::string vp = "/bufferViews/" + std::to_string(a.bufferView);
        const tinygltf::Buffer& b = element(m_model.buffers, v.buffer, vp + "/buffer", "buffer");
        const std::string bp = "/buffers/" + std::to_string(v.buffer);
        if (b.data.empty()) fail(bp, "the buffer is missing or empty" + used);
        // Sizes from the file may be anything: compare without overflow.
        if (v.byteOffset > b.data.size() || v.byteLength > b.data.size() - v.byteOffset) {
            fail(vp, "byte offset " + idx(v.byteOffset) + " + length " + idx(v.byteLength) +
                         " lies beyond the buffer's " + idx(b.data.size()) + " bytes");
        }
        const std::size_t elem =
            std::size_t(tinygltf::GetComponentSizeInBytes(std::uint32_t(a.componentType))) *
            std::size_t(tinygltf::GetNumComponentsInType(std::uint32_t(a.type)));
        const std::size_t stride = v.byteStride ? v.byteStride : elem;
        if (stride < elem) {
            fail(vp + "/byteStride", "stride " + idx(stride) + " is smaller than the element (" +
                                         idx(elem) + " bytes)" + used);
        }
        Elements e;
        e.count = a.count;
        e.stride = stride;
        e.component = a.componentType;
        e.type = a.type;
        if (a.count == 0) return e;
        // byteOffset + stride (count - 1) + elem <= byteLength, without overflow.
        if (a.byteOffset > v.byteLength || elem > v.byteLength - a.byteOffset ||
            (a.count - 1) > (v.byteLength - a.byteOffset - elem) / stride) {
            fail(ap, idx(a.count) + " elements of stride " + idx(stride) + " from offset " +
                         idx(a.byteOffset) + " do not fit the buffer view's " + idx(v.byteLength) +
                         " bytes" + used);
        }
        e.data = b.data.data() + v.byteOffset + a.byteOffset;
        return e;
    }

    std::vector<Vec3> vec3s(int index, const std::string& user, const char* what) const {
        const Elements e =
            accessor(index, user, {TINYGLTF_TYPE_VEC3}, {TINYGLTF_COMPONENT_TYPE_FLOAT});
        std::vector<Vec3> out(e.count);
        for (std::size_t i = 0; i < e.count; ++i) {
            std::memcpy(&out[i], e.data + i * e.stride, sizeof(Vec3));
            if (!is_finite(out[i])) {
                fail("/accessors/" + std::to_string(index),
                     std::string(what) + " " + idx(i) + " is not finite (used by " + user + ")");
            }
        }
        return out;
    }

    // TEXCOORD_0: float, or normalised unsigned byte / short (glTF 3.7.2.1), turned from glTF's
    // top-left origin to Facet's bottom-left: (u, v) -> (u, 1 - v).
    std::vector<Vec2> texcoords(int index, const std::string& user, std::size_t nvert) const {
        const Elements e =
            accessor(index, user, {TINYGLTF_TYPE_VEC2},
                     {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                      TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT});
        const std::string ap = "/accessors/" + std::to_string(index);
        if (e.count != nvert)
            fail(ap, idx(e.count) + " texture coordinates for " + idx(nvert) +
                         " positions (used by " + user + ")");
        std::vector<Vec2> out(e.count);
        for (std::size_t i = 0; i < e.count; ++i) {
            const unsigned char* p = e.data + i * e.stride;
            Vec2 uv;
            if (e.component == TINYGLTF_COMPONENT_TYPE_FLOAT) {
                std::memcpy(&uv, p, sizeof uv);
            } else if (e.component == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
                uv = Vec2(float(p[0]) / 255.f, float(p[1]) / 255.f);
            } else {
                std::uint16_t s[2];
                std::memcpy(s, p, sizeof s);
                uv = Vec2(float(s[0]) / 65535.f, float(s[1]) / 65535.f);
            }
            if (!std::isfinite(uv.x) || !std::isfinite(uv.y))
                fail(ap, "texture coordinate " + idx(i) + " is not finite (used by " + user + ")");
            out[i] = Vec2(uv.x, 1.f - uv.y);
        }
        return out;
    }

    // COLOR_0 (glTF 3.7.2.1: VEC3 or VEC4, float or normalised unsigned byte / short; linear
    // RGB(A), alpha 1 for VEC3). Float channels outside [0, 1] are errors.
    std::vector<glm::vec4> colors(int index, const std::string& user, std::size_t nvert) const {
        const Elements e =
            accessor(index, user, {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4},
                     {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                      TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT});
        const std::string ap = "/accessors/" + std::to_string(index);
        if (e.count != nvert)
            fail(ap,
                 idx(e.count) + " colours for " + idx(nvert) + " positions (used by " + user + ")");
        const std::size_t nc = e.type == TINYGLTF_TYPE_VEC4 ? 4 : 3;
        std::vector<glm::vec4> out(e.count, glm::vec4(1.f));
        for (std::size_t i = 0; i < e.count; ++i) {
            const unsigned char* p = e.data + i * e.stride;
            for (std::size_t c = 0; c < nc; ++c) {
                float v;
                if (e.component == TINYGLTF_COMPONENT_TYPE_FLOAT) {
                    std::memcpy(&v, p + 4 * c, 4);
                } else if (e.component == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
                    v = float(p[c]) / 255.f;
                } else {
                    std::uint16_t u;
                    std::memcpy(&u, p + 2 * c, 2);
                    v = float(u) / 65535.f;
                }
                if (!(v >= 0.f && v <= 1.f))
                    fail(ap, "colour " + idx(i) + " has a channel outside [0, 1] (used by " + user +
                                 ")");
                out[i][int(c)] = v;
            }
        }
        return out;
    }

    // TANGENT (glTF 3.7.2.1: VEC4 float, xyz unit, w = +-1 the bitangent sign).
    std::vector<glm::vec4> tangents(int index, const std::string& user) const {
        const Elements e =
            accessor(index, user, {TINYGLTF_TYPE_VEC4}, {TINYGLTF_COMPONENT_TYPE_FLOAT});
        std::vector<glm::vec4> out(e.count);
        for (std::size_t i = 0; i < e.count; ++i) {
            std::memcpy(&out[i], e.data + i * e.stride, sizeof(glm::vec4));
            const glm::vec4& t = out[i];
            if (!std::isfinite(t.x) || !std::isfinite(t.y) || !std::isfinite(t.z) ||
                !std::isfinite(t.w) || t.w == 0.f)
                fail("/accessors/" + std::to_string(index),
                     "tangent " + idx(i) + " is not finite or has a zero sign (used by " + user +
                         ")");
        }
        return out;
    }

    std::vector<std::uint32_t> indices(int index, const std::string& user,
                                       std::size_t num_vertices) const {
        const Elements e =
            accessor(index, user, {TINYGLTF_TYPE_SCALAR},
                     {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                      TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT});
        std::vector<std::uint32_t> out(e.count);
        for (std::size_t i = 0; i < e.count; ++i) {
            const unsigned char* p = e.data + i * e.stride;
            std::uint32_t v = 0;
            if (e.component == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
                v = *p;
            } else if (e.component == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
                std::uint16_t s;
                std::memcpy(&s, p, 2);
                v = s;
            } else {
                std::memcpy(&v, p, 4);
            }
            if (v >= num_vertices) {
                fail("/accessors/" + std::to_string(index),
                     "index " + idx(i) + " is " + std::to_string(v) + ", out of range [0, " +
                         std::to_string(std::int64_t(num_vertices) - 1) + "] (used by " + user +
                         ")");
            }
            out[i] = v;
        }
        return out;
    }

    // Triangle lists from the primitive's mode (glTF 3.7.2.1: strips and fans).
    std::vector<std::uint32_t> triangle_list(std::vector<std::uint32_t> ix, int mode,
                                             const std::string& pp) const {
        std::vector<std::uint32_t> t;
        if (mode == TINYGLTF_MODE_TRIANGLES) {
            if (ix.size() % 3 != 0) {
                fail(pp, "TRIANGLES with " + idx(ix.size()) + " vertices (not a multiple of 3)");
            }
            return ix;
        }
        for (std::size_t i = 0; i + 2 < ix.size(); ++i) {
            if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
                // Triangle i: {v_i, v_(i+1+i%2), v_(i+2-i%2)}: every triangle keeps the winding.
                t.insert(t.end(), {ix[i], ix[i + 1 + i % 2], ix[i + 2 - i % 2]});
            } else {
                // Fan triangle i: {v_(i+1), v_(i+2), v_0}.
                t.insert(t.end(), {ix[i + 1], ix[i + 2], ix[0]});
            }
        }
        return t;
    }

    // Whether nodes share mesh `mesh_index` (share_meshes): used by several nodes, and none of
    // its primitives' materials emits (an emitter is a light per placement: copied instead).
    bool shared(int mesh_index) const {
        if (!m_share || mesh_index < 0 || std::size_t(mesh_index) >= m_uses.size() ||
            m_uses[std::size_t(mesh_index)] < 2)
            return false;
        for (const tinygltf::Primitive& pr : m_model.meshes[std::size_t(mesh_index)].primitives) {
            if (pr.material < 0 || std::size_t(pr.material) >= m_out.materials.size()) continue;
            const GltfMaterial& gm = m_out.materials[std::size_t(pr.material)];
            if (gm.emission != Rgb(0.f) || gm.emission_texture) return false;
        }
        return true;
    }

    void mesh(int mesh_index, const glm::dmat4& world, const std::string& np) {
        if (shared(mesh_index)) {
            const double det = glm::determinant(glm::dmat3(world));
            if (!(std::fabs(det) > 0.0) || !std::isfinite(det)) {
                report(np + "/singular", np,
                       "the node's transform is singular (zero scale) or not finite: its mesh "
                       "is skipped");
                return;
            }
            auto [at, fresh] = m_prototype_of.try_emplace(mesh_index, m_out.num_prototypes);
            if (fresh) {
                // The mesh once, in its own frame; each node places it.
                const std::size_t first = m_out.parts.size();
                mesh_copy(mesh_index, glm::dmat4(1.0), np);
                for (std::size_t i = first; i < m_out.parts.size(); ++i)
                    m_out.parts[i].prototype = at->second;
                ++m_out.num_prototypes;
            }
            m_out.placements.push_back({at->second, world});
            return;
        }
        mesh_copy(mesh_index, world, np);
    }

    // The mesh's primitives as parts, transformed by `world`.
    void mesh_copy(int mesh_index, const glm::dmat4& world, const std::string& np) {
        const tinygltf::Mesh& me = element(m_model.meshes, mesh_index, np + "/mesh", "mesh");
        const glm::dmat3 lin(world);
        const double det = glm::determinant(lin);
        if (!(std::fabs(det) > 0.0) || !std::isfinite(det)) {
            report(np + "/singular", np,
                   "the node's transform is singular (zero scale) or not finite: its mesh is "
                   "skipped");
            return;
        }
        const glm::dmat3 normal_mat = glm::transpose(glm::inverse(lin));
        const std::string mp = "/meshes/" + std::to_string(mesh_index);
        for (std::size_t pi = 0; pi < me.primitives.size(); ++pi) {
            const tinygltf::Primitive& pr = me.primitives[pi];
            const std::string pp = mp + "/primitives/" + idx(pi);
            const int mode = pr.mode < 0 ? TINYGLTF_MODE_TRIANGLES : pr.mode;
            if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
                mode != TINYGLTF_MODE_TRIANGLE_FAN) {
                report("mode" + std::to_string(mode), pp + "/mode",
                       "points and lines (mode " + std::to_string(mode) +
                           ") are not imported: Facet renders surfaces");
                continue;
            }
            if (pr.extensions.count("KHR_draco_mesh_compression")) {
                report("draco", pp + "/extensions/KHR_draco_mesh_compression",
                       "Draco compression is not decoded: the primitive's uncompressed "
                       "accessors are read");
            }
            if (!pr.targets.empty()) {
                report("targets", pp + "/targets",
                       "morph targets are not applied (the base shape is imported)");
            }
            for (const auto& [name, _] : pr.attributes) {
                if (name == "POSITION" || name == "NORMAL" || name == "TEXCOORD_0" ||
                    name == "TANGENT" || name == "COLOR_0")
                    continue;
                const std::string key = name.rfind("TEXCOORD_", 0) == 0 ? "uv"
                                        : name.rfind("COLOR_", 0) == 0  ? "color"
                                                                        : name;
                const char* what = key == "uv"      ? "only TEXCOORD_0 is imported"
                                   : key == "color" ? "only COLOR_0 is imported"
                                                    : "this attribute is not imported";
                report("attr:" + key, pp + "/attributes/" + name, what);
            }
            auto pos = pr.attributes.find("POSITION");
            if (pos == pr.attributes.end()) fail(pp + "/attributes", "has no POSITION");
            TriangleMesh m;
            m.positions = vec3s(pos->second, pp + "/attributes/POSITION", "position");
            const std::size_t nvert = m.positions.size();
            if (auto n = pr.attributes.find("NORMAL"); n != pr.attributes.end()) {
                m.normals = vec3s(n->second, pp + "/attributes/NORMAL", "normal");
                if (m.normals.size() != nvert) {
                    fail(pp + "/attributes/NORMAL",
                         idx(m.normals.size()) + " normals for " + idx(nvert) + " positions");
                }
            }
            if (auto t = pr.attributes.find("TEXCOORD_0"); t != pr.attributes.end())
                m.uvs = texcoords(t->second, pp + "/attributes/TEXCOORD_0", nvert);
            if (auto c = pr.attributes.find("COLOR_0"); c != pr.attributes.end())
                m.colors = colors(c->second, pp + "/attributes/COLOR_0", nvert);
            if (auto t = pr.attributes.find("TANGENT"); t != pr.attributes.end()) {
                m.tangents = tangents(t->second, pp + "/attributes/TANGENT");
                if (m.tangents.size() != nvert) {
                    fail(pp + "/attributes/TANGENT",
                         idx(m.tangents.size()) + " tangents for " + idx(nvert) + " positions");
                }
                // xyz as directions through the node transform; a mirroring transform
                // reverses the bitangent's handedness.
                for (glm::vec4& t4 : m.tangents) {
                    const glm::dvec3 w = lin * glm::dvec3(Vec3(t4));
                    const double l = glm::length(w);
                    t4 = glm::vec4(l > 0.0 ? Vec3(w / l) : Vec3(0.f), det < 0.0 ? -t4.w : t4.w);
                }
            }
            std::vector<std::uint32_t> ix;
            if (pr.indices >= 0) {
                ix = indices(pr.indices, pp + "/indices", nvert);
            } else {
                ix.resize(nvert);
                for (std::size_t i = 0; i < nvert; ++i) ix[i] = std::uint32_t(i);
            }
            m.indices = triangle_list(std::move(ix), mode, pp);
            if (m.indices.empty()) {
                report(pp + "/empty", pp, "the primitive has no triangles; skipped");
                continue;
            }
            for (Vec3& p : m.positions)
                p = Vec3(glm::dvec3(world * glm::dvec4(glm::dvec3(p), 1.0)));
            for (Vec3& n : m.normals) {
                const glm::dvec3 w = normal_mat * glm::dvec3(n);
                const double l = glm::length(w);
                if (!(l > 0.0)) {
                    report(pp + "/zero-normal", pp + "/attributes/NORMAL",
                           "contains zero-length normals: the primitive is shaded flat");
                    m.normals.clear();
                    break;
                }
                n = Vec3(w / l);
            }
            // A mirroring node transform reverses the winding (glTF 3.7.4): undo it.
            if (det < 0.0) {
                for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
                    std::swap(m.indices[t + 1], m.indices[t + 2]);
                }
            }
            GltfPart part;
            part.pointer = pp;
            part.mesh = std::move(m);
            if (pr.material >= 0) {
                element(m_model.materials, pr.material, pp + "/material", "material");
                part.material = pr.material;
            } else {
                part.material = default_material(pp);
            }
            m_out.parts.push_back(std::move(part));
        }
    }

    std::string m_path, m_file;
    std::string_view m_memory;
    bool m_in_memory = false;
    tinygltf::Model m_model;
    GltfImport m_out;
    std::set<std::string> m_reported;
    std::vector<bool> m_seen;
    int m_default = -1;
    ImageBytes m_image_bytes;  // encoded images by index (keep_image)
    bool m_share = false;
    std::vector<int> m_uses;            // per mesh: the nodes that use it (m_share)
    std::map<int, int> m_prototype_of;  // shared mesh -> GltfPart::prototype
};

// All parts as one mesh (the exporters' `triangles`, and a shape whose "material" replaces the
// file's).
TriangleMesh merged(const GltfImport& g) {
    TriangleMesh out;
    for (const GltfPart& p : g.parts) {
        const std::uint32_t base = std::uint32_t(out.positions.size());
        out.positions.insert(out.positions.end(), p.mesh.positions.begin(), p.mesh.positions.end());
        for (std::uint32_t i : p.mesh.indices) out.indices.push_back(base + i);
    }
    // Normals only when every part has them (a mesh has one normal per position or none).
    bool all = !g.parts.empty();
    for (const GltfPart& p : g.parts) all = all && !p.mesh.normals.empty();
    if (all) {
        for (const GltfPart& p : g.parts) {
            out.normals.insert(out.normals.end(), p.mesh.normals.begin(), p.mesh.normals.end());
        }
    }
    // UVs likewise (a shape "material" with textures needs them everywhere).
    bool uvs = !g.parts.empty();
    for (const GltfPart& p : g.parts) uvs = uvs && !p.mesh.uvs.empty();
    if (uvs)
        for (const GltfPart& p : g.parts)
            out.uvs.insert(out.uvs.end(), p.mesh.uvs.begin(), p.mesh.uvs.end());
    // Tangents likewise.
    bool all_tangents = !g.parts.empty();
    for (const GltfPart& p : g.parts) all_tangents = all_tangents && !p.mesh.tangents.empty();
    for (const GltfPart& p : g.parts) {
        if (all_tangents)
            out.tangents.insert(out.tangents.end(), p.mesh.tangents.begin(), p.mesh.tangents.end());
    }
    return out;
}

TriangleMesh triangles(const ShapeDesc& s, const std::string& base_dir) {
    return merged(import_gltf(resolve_scene_path(s.file, base_dir)));
}

bool replaces_materials(const ShapeDesc& s) {
    return s.material || !s.material_ref.empty();
}

// The base colour times the vertex colour: its texture tinted per hit, or a constant factor as
// the scale of a vertex-colour texture.
MaterialDesc gltf_vertex_colored(const MaterialDesc& desc) {
    MaterialDesc d = desc;
    if (auto t = d.textures.find("base_color"); t != d.textures.end()) {
        t->second.times_vertex_color = true;
    } else {
        TextureDesc v;
        v.kind = "vertex_color";
        v.color_scale = std::get<Rgb>(d.params.values().at("base_color"));
        ParamSet rest;
        for (const auto& [key, value] : d.params.values())
            if (key != "base_color") rest.set(key, value);
        d.params = std::move(rest);
        d.textures["base_color"] = v;
    }
    return d;
}

void build(ShapeBuild& b) {
    const ShapeDesc& s = b.shape;
    const std::string fp = b.ptr + "/file";
    if (!b.files_allowed()) b.fail(fp, "files are disabled here");
    GltfImport g;
    // Meshes that several nodes use are stored once and placed as instances (embree_scene.cpp),
    // unless the shape's own material replaces the file's (then one merged mesh) or the shape
    // is itself in a prototype (one level of instancing).
    const bool share = b.can_instance() && !replaces_materials(s);
    try {
        g = import_gltf(resolve_scene_path(s.file, b.base_dir()), share);
    } catch (const std::exception& e) {
        b.fail(fp, e.what());
    }
    for (const std::string& r : g.reports) b.warn(b.place() + ": " + r);
    if (g.num_cameras > 0) {
        b.warn(b.place() + ": " + std::filesystem::path(s.file).filename().string() +
               "#/cameras: " + std::to_string(g.num_cameras) +
               " camera(s) not used by a gltf shape (`facet render` on the bare file uses the "
               "first perspective one)");
    }
    if (g.parts.empty()) {
        b.fail(fp,
               "the file's scene has no triangle primitives (nothing to render; see the "
               "warnings for what was skipped)");
    }
    std::uint64_t n = 0;
    for (const GltfPart& p : g.parts) n += p.mesh.num_triangles();
    b.reserve_triangles(n, fp);
    if (replaces_materials(s)) {
        // The shape's own material (and emission) for every primitive.
        b.add_triangles(merged(g), Vec3(0.f));
        return;
    }
    if (b.emissive) {
        b.fail(b.ptr + "/emission",
               "a gltf shape emits what its file's materials emit (emissiveFactor); give the "
               "shape a \"material\" to replace the file's materials and emit this instead");
    }
    // Per material, built without and with COLOR_0 (glTF 3.9.2: a primitive's vertex colour
    // multiplies its base colour, factor and texture alike).
    std::vector<std::array<std::optional<ShapeSurface>, 2>> built(g.materials.size());
    std::vector<std::uint32_t> prototypes;
    for (int i = 0; i < g.num_prototypes; ++i) prototypes.push_back(b.add_local_prototype());
    for (GltfPart& p : g.parts) {
        const GltfMaterial& gm = g.materials[std::size_t(p.material)];
        const bool colored = !p.mesh.colors.empty();
        std::optional<ShapeSurface>& mat = built[std::size_t(p.material)][colored ? 1 : 0];
        if (!mat) {
            mat = b.add_material(colored ? gltf_vertex_colored(gm.desc) : gm.desc, fp,
                                 &kGltfConversion);
            if (gm.emission_texture)
                mat->emission_texture = b.add_texture(*gm.emission_texture, fp, true, true);
        }
        if (colored && mat->opacity.active() &&
            std::any_of(p.mesh.colors.begin(), p.mesh.colors.end(),
                        [](const glm::vec4& c) { return c.a != 1.f; }))
            b.warn(s.file + "#" + p.pointer +
                   "/attributes/COLOR_0: the vertex colours' alpha does not multiply the "
                   "material's opacity (" +
                   gm.pointer + " alphaMode); their RGB does multiply the base colour");
        ShapeSurface su = *mat;
        su.material_name = s.file + "#" + gm.pointer;
        su.emission = gm.emission;
        const bool uv_textured = (su.textured >= 0 && b.textured_uses_uv(su.textured)) ||
                                 su.emission_texture || su.opacity.texture;
        if (uv_textured && p.mesh.uvs.empty())
            b.fail(fp, std::filesystem::path(s.file).filename().string() + "#" + p.pointer +
                           "/attributes: the primitive's material " + gm.pointer +
                           " has textures but the primitive has no TEXCOORD_0");
        su.two_sided = gm.double_sided && s.two_sided;
        if (p.prototype >= 0)
            b.add_part_to(prototypes[std::size_t(p.prototype)], std::move(p.mesh), std::move(su));
        else
            b.add_part(std::move(p.mesh), std::move(su));
    }
    for (const GltfPlacement& pl : g.placements)
        b.place_prototype(prototypes[std::size_t(pl.prototype)], pl.to_object);
}

// POV-Ray: one mesh with the shape's material when it replaces the file's; a file's several
// materials have no export yet.
void pov(PovShapeOut& o) {
    if (replaces_materials(o.shape)) return o.triangles(false);
    o.fail(o.pointer + "/file",
           "export-pov cannot write a glTF file's own materials yet; give the shape a "
           "\"material\" to export its triangles with that one");
}

}  // namespace

void gltf_composite_values(const DVec3* sources, DVec3* outputs) {
    const Rgb base(sources[0]);
    const double metal = sources[1].x, rough = sources[2].x;
    Rgb f0;
    for (int c = 0; c < 3; ++c) f0[c] = float(kDielectricF0 * (1.0 - metal) + base[c] * metal);
    outputs[0] = DVec3(base * float(1.0 - metal));
    outputs[1] = DVec3(rough * rough);
    outputs[2] = DVec3(f0);
}

ParamSet gltf_composite_params(const ParamSet& sources) {
    const auto& v = sources.values();
    const DVec3 in[3] = {DVec3(std::get<Rgb>(v.at("base_color"))),
                         DVec3(std::get<double>(v.at("metallic"))),
                         DVec3(std::get<double>(v.at("roughness")))};
    DVec3 out[3];
    gltf_composite_values(in, out);
    ParamSet p;
    p.set("diffuse_reflectance", Rgb(out[0]));
    p.set("distribution", std::string("ggx"));
    p.set("alpha", out[1].x);
    p.set("fresnel", std::string("schlick"));
    p.set("f0", Rgb(out[2]));
    return p;
}

void apply_khr_texture_transform(TextureDesc& d, Vec2 offset, double rotation, Vec2 scale) {
    constexpr double kPi = 3.14159265358979323846;
    const double s = std::sin(rotation), c = std::cos(rotation);
    d.uv_scale = scale;
    d.uv_rotation = -rotation * 180.0 / kPi;
    d.uv_offset = Vec2(float(double(offset.x) - double(scale.y) * s),
                       float(1.0 - double(offset.y) - double(scale.y) * c));
}

GltfImport import_gltf(const std::string& path, bool share_meshes) {
    return Importer(path, share_meshes).run();
}

GltfImport parse_gltf(std::string_view bytes, const std::string& name) {
    return Importer(bytes, name).run();
}

SceneDescription gltf_scene_description(const std::string& path, int width, int height,
                                        std::vector<std::string>& notes) {
    const GltfImport g = import_gltf(path);
    SceneDescription d;
    d.description = "the glTF file " + path;
    const std::filesystem::path p(path);
    d.base_dir = p.has_parent_path() ? p.parent_path().string() : ".";
    ShapeDesc s;
    s.kind = ShapeKind::Gltf;
    s.name = p.filename().string();
    s.file = p.filename().string();
    d.shapes.push_back(s);
    LightDesc env;
    env.kind = LightKind::Environment;
    env.radiance = Rgb(1.f);
    d.lights.push_back(env);
    notes.push_back("lit by a constant white environment of radiance 1");
    CameraDesc& c = d.camera;
    c.width = width;
    c.height = height;
    if (g.camera) {
        const GltfCamera& gc = *g.camera;
        c.position = Vec3(gc.position);
        c.look_at = Vec3(gc.position + glm::normalize(gc.forward));
        c.up = Vec3(glm::normalize(gc.up));
        c.fov = gc.yfov_deg;
        if (gc.aspect) c.width = std::max(1, int(std::lround(height * *gc.aspect)));
        notes.push_back("using the file's camera " + gc.pointer);
        return d;
    }
    // No camera: look at the bounding sphere of every part from the front-right, above
    // (glTF's +z front is -y after the Z-up turn), at the distance where the sphere fills
    // the smaller field of view.
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const GltfPart& pt : g.parts) {
        for (const Vec3& v : pt.mesh.positions) {
            lo = glm::min(lo, glm::dvec3(v));
            hi = glm::max(hi, glm::dvec3(v));
        }
    }
    if (g.parts.empty()) lo = hi = glm::dvec3(0.0);
    const glm::dvec3 centre = 0.5 * (lo + hi);
    const double radius = std::max(0.5 * glm::length(hi - lo), 1e-6);
    c.fov = 40.0;
    const double half = 0.5 * c.fov * M_PI / 180.0 * std::min(1.0, double(width) / height);
    const double dist = 1.1 * radius / std::sin(half);
    const glm::dvec3 dir = glm::normalize(glm::dvec3(0.6, -1.0, 0.5));
    c.position = Vec3(centre + dist * dir);
    c.look_at = Vec3(centre);
    c.up = Vec3(0.f, 0.f, 1.f);
    notes.push_back("the file has no camera: framing its bounding box from the front (fov 40)");
    return d;
}

extern const ShapeKindDef kGltfKind{
    ShapeKind::Gltf,
    "gltf",
    "every triangle primitive of a glTF 2.0 file (`.gltf` or `.glb`, tinygltf) with its node "
    "transforms, turned Z-up ((x, y, z) -> (x, -z, y)) before `transform`, and its "
    "metallic-roughness materials as `composite` with their base colour, metallic-roughness and "
    "emissive textures (TEXCOORD_0, v -> 1 - v; samplers; KHR_texture_transform), its normal "
    "textures as normal maps (TANGENT or MikkTSpace tangents) and alphaMode as opacity "
    "(docs/gltf.md); `material`, when given, replaces the file's materials; what is "
    "not converted is reported",
    {{"file", FieldType::Path, true, &ShapeDesc::file, "-",
      "the glTF file, relative to the scene file; per material, with b = baseColorFactor x "
      "baseColorTexture, m = metallicFactor x texture B, r = roughnessFactor x texture G: "
      "diffuse_reflectance = b (1 - m), ggx alpha = r^2, schlick f0 = 0.04 (1 - m) + b m, "
      "emission = emissiveFactor x emissiveTexture x emissiveStrength, opacity = base alpha "
      "(MASK: cut at alphaCutoff; BLEND), two_sided = doubleSided and `two_sided`"}},
    build,
    triangles,
    pov,
    true};

}  // namespace facet::render
