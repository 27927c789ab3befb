// build_scene's materials (scene_builder.h): the named media, the named and inline materials
// (reflection model, combinations, opacity, interior medium), the textures of their
// parameters, normal and bump maps, and the staged per-hit build of a textured material.
// Shapes (build_shapes.cpp) call build_material and build_texture for what they reference.

#include <algorithm>
#include <filesystem>
#include <optional>
#include <sstream>

#include "facet/reflectance.h"
#include "facet/render/kinds.h"
#include "scene_builder.h"
#include "textures/texture_build.h"

namespace facet::render::detail {

// "unknown medium 'x'" with a did-you-mean among the scene's medium names.
std::string Builder::unknown_medium(const std::string& name) const {
    std::vector<std::string> names;
    for (const auto& [n, _] : m_desc.media) names.push_back(n);
    std::string msg = "unknown medium '" + name + "'";
    const std::string g = closest_name(name, names);
    if (!g.empty()) {
        msg += " (did you mean '" + g + "'?)";
    } else if (names.empty()) {
        msg += " (the scene defines no \"media\")";
    }
    return msg;
}

// What a medium kind's builder gets (kind_build.h).
class Builder::MediumContext final : public MediumBuild {
  public:
    explicit MediumContext(Builder& b) : m_b(b) {}
    [[noreturn]] void fail(const std::string& p, const std::string& m) const override {
        m_b.fail(p, m);
    }
    bool files_allowed() const override { return m_b.m_limits.allow_files; }
    const std::string& base_dir() const override { return m_b.m_desc.base_dir; }

  private:
    Builder& m_b;
};

// The named media (their kinds validate them) and the world medium.
void Builder::build_media() {
    for (const auto& [name, m] : m_desc.media) {
        const std::string ptr = "/media/" + escape_pointer_token(name);
        if (m_medium_index.count(name)) fail(ptr, "duplicate medium name '" + name + "'");
        const MediumKindDef* k = find_medium_kind(m.kind);
        if (!k) fail(ptr + "/kind", "unknown medium kind");
        m_medium_index[name] = std::int32_t(m_builder.media().size());
        m_builder.media().push_back(k->build(m, ptr, MediumContext(*this)));
    }
    if (!m_desc.world_medium.empty()) {
        const auto it = m_medium_index.find(m_desc.world_medium);
        if (it == m_medium_index.end()) fail("/world_medium", unknown_medium(m_desc.world_medium));
        m_builder.world_medium() = it->second;
        // An escaping ray crosses the world medium over an infinite length: its emission
        // would be infinite where nothing attenuates it.
        const Medium& w = m_builder.media()[std::size_t(it->second)];
        for (int c = 0; c < 3; ++c)
            if (w.emission()[c] > 0.f && !(w.sigma_t()[c] > 0.f))
                fail("/world_medium",
                     "the world medium '" + m_desc.world_medium +
                         "' emits where it neither absorbs nor scatters: rays that escape "
                         "would gather infinite emission");
    }
}

// The key "interior" of a material (scenes/FORMAT.md, "Media"): the name of the medium its
// shapes bound, taken out of `m` (it belongs to no reflection model).
std::int32_t Builder::take_interior(MaterialDesc& m, const std::string& ptr) {
    const auto it = m.params.values().find("interior");
    if (it == m.params.values().end()) return -1;
    const std::string p = ptr + "/interior";
    const std::string* name = std::get_if<std::string>(&it->second);
    if (!name) fail(p, "expected the name of a medium of \"media\"");
    const auto found = m_medium_index.find(*name);
    if (found == m_medium_index.end()) fail(p, unknown_medium(*name));
    ParamSet rest;
    for (const auto& [key, v] : m.params.values())
        if (key != "interior") rest.set(key, v);
    m.params = std::move(rest);
    return found->second;
}

// The keys "opacity" (a number or a texture) and "alpha_cutoff" of a material, which belong
// to no reflection model (scenes/FORMAT.md, "Opacity"): validated, and taken out of `m`.
Opacity Builder::build_opacity(MaterialDesc& m, const std::string& ptr) {
    Opacity o;
    auto number = [&](const char* key, double lo, const char* range) -> std::optional<double> {
        const auto it = m.params.values().find(key);
        if (it == m.params.values().end()) return std::nullopt;
        const std::string p = ptr + "/" + key;
        const double* d = std::get_if<double>(&it->second);
        if (!d) fail(p, std::string("expected a number ") + range);
        return check_range(*d, p, lo, 1.0, range);
    };
    const std::optional<double> value = number("opacity", 0.0, "in [0, 1]");
    const std::optional<double> cutoff = number("alpha_cutoff", 1e-30, "in (0, 1]");
    if (value) o.value = float(*value);
    if (auto it = m.textures.find("opacity"); it != m.textures.end()) {
        const std::string op = ptr + "/opacity";
        const TextureDesc& td = it->second;
        if (td.kind == "vertex_color" || td.times_vertex_color)
            fail(op,
                 "a vertex colour cannot be an opacity (cut-outs are decided during "
                 "traversal, before the hit's colour is known)");
        TexelImageOptions linear;
        linear.color_space = ColorSpace::Linear;
        if (td.kind == "image" && td.channel == "a" && !td.file.empty() &&
            (m_limits.allow_files || td.bytes || td.image) &&
            load_image(td, linear, op)->alpha_channel < 0) {
            // The alpha of an image without one is 1 (opaque), as glTF and Blender read it:
            // the opacity is the texture's scale alone.
            o.value = float(check_range(td.scale * double(td.color_scale.r), op + "/scale", 0.0,
                                        1.0, "in [0, 1]"));
            m.textures.erase(it);
        } else {
            o.texture = build_texture(td, op, false, false);
            if (o.texture->uses_position() || o.texture->uses_view() || o.texture->uses_strand() ||
                o.texture->uses_ray())
                fail(op,
                     "an opacity reads UVs only (cut-outs are decided during traversal): "
                     "give the procedural texture \"coordinates\": \"uv\"");
            if (!(o.texture->min_value().r >= 0.f) || !(o.texture->max_value().r <= 1.f))
                fail(op, "the texture's values must lie in [0, 1]");
            m.textures.erase(it);
        }
    }
    if (cutoff) {
        o.cutoff = float(*cutoff);
        if (!o.texture) o.value = o.value >= o.cutoff ? 1.f : 0.f;
    }
    if (value || cutoff) {
        ParamSet rest;
        for (const auto& [key, v] : m.params.values())
            if (key != "opacity" && key != "alpha_cutoff") rest.set(key, v);
        m.params = std::move(rest);
    }
    return o;
}

// The image of texture `d` (a file, or encoded bytes in memory), through the scene's cache.
std::shared_ptr<const TexelImage> Builder::load_image(const TextureDesc& d,
                                                      const TexelImageOptions& opt,
                                                      const std::string& ptr) {
    try {
        if (d.image) {
            // In memory (numpy): decoded when it was made; counted against the bound, and
            // checked here for what a file is checked on load.
            auto img = m_images.adopt(d.image, ptr + "/texture");
            for (std::size_t i = 0; opt.reject_negative && i < img->texels.size(); ++i)
                if (img->texels[i] < 0.f &&
                    int(i % std::size_t(img->channels)) != img->alpha_channel)
                    fail(ptr + "/texture", d.file + ": texel " +
                                               std::to_string(i / std::size_t(img->channels)) +
                                               " is negative (an emitted radiance)");
            return img;
        }
        return d.bytes ? m_images.get_memory(d.file, *d.bytes, opt, ptr + "/texture")
                       : m_images.get(resolve_scene_path(d.file, m_desc.base_dir), opt,
                                      ptr + "/texture");
    } catch (const TexelImageError& e) {
        throw SceneError(m_name + ": " + e.what());
    }
}

// "unknown material 'x'" with a did-you-mean among the scene's material names.
std::string Builder::unknown_material(const std::string& name) const {
    std::vector<std::string> names;
    for (const auto& [n, _] : m_desc.materials) names.push_back(n);
    std::string msg = "unknown material '" + name + "'";
    std::string g = closest_name(name, names);
    if (!g.empty()) {
        msg += " (did you mean '" + g + "'?)";
    } else if (names.empty()) {
        msg += " (the scene defines no \"materials\")";
    }
    return msg;
}

// The named material `name`, built on first use (a combination may name a material that
// the file lists after it); `ref_ptr` is the pointer of the reference, for errors. A chain
// of references that comes back to a material being built is a cycle: an error.
Builder::BuiltMaterial Builder::named_material(const std::string& name,
                                               const std::string& ref_ptr) {
    if (auto it = m_named.find(name); it != m_named.end()) return it->second;
    const auto d = m_named_desc.find(name);
    if (d == m_named_desc.end()) fail(ref_ptr, unknown_material(name));
    if (std::find(m_building.begin(), m_building.end(), name) != m_building.end()) {
        std::string chain;
        for (auto it = std::find(m_building.begin(), m_building.end(), name);
             it != m_building.end(); ++it)
            chain += "'" + *it + "' -> ";
        fail(ref_ptr, "material '" + name + "' refers to itself (" + chain + "'" + name + "')");
    }
    m_building.push_back(name);
    const BuiltMaterial bm = build_material(*d->second, "/materials/" + escape_pointer_token(name));
    m_building.pop_back();
    m_named[name] = bm;
    return bm;
}

// The children of a combination (ModelInfo::children of them, under ptr/materials).
std::vector<Builder::BuiltMaterial> Builder::build_children(const MaterialDesc& m,
                                                            const ModelInfo& info,
                                                            const std::string& ptr) {
    if (int(m.materials.size()) != info.children) {
        fail(ptr + "/materials",
             info.children == 0
                 ? "model '" + m.model + "' takes no sub-materials"
                 : "model '" + m.model + "' needs exactly " + std::to_string(info.children) +
                       " materials [a, b] (got " + std::to_string(m.materials.size()) + ")");
    }
    std::vector<BuiltMaterial> children;
    for (std::size_t k = 0; k < m.materials.size(); ++k) {
        const MaterialDesc& c = m.materials[k];
        const std::string cp = ptr + "/materials/" + std::to_string(k);
        if (!c.ref.empty()) {
            if (!c.model.empty() || !c.params.values().empty() || !c.materials.empty())
                fail(cp, "give either a material name or an inline material, not both");
            children.push_back(named_material(c.ref, cp));
        } else {
            children.push_back(build_material(c, cp));
        }
    }
    return children;
}

// Warns when an `add` reflects more than it receives (allowed, as in Cycles): its
// directional albedo at a few angles (Gauss-Legendre order 16, reflection only).
void Builder::check_energy_gain(const MaterialDesc& m, const Material& mat,
                                const std::string& ptr) {
    if (m.model != "add") return;
    float worst = 0.f, worst_mu = 1.f;
    for (float mu : {1.f, 0.7f, 0.4f, 0.1f}) {
        const Vec3 w(std::sqrt(1.f - mu * mu), 0.f, mu);
        const DVec3 r = hemispherical_directional(mat, w, 16).value;
        const float rmax = float(std::max({r.x, r.y, r.z}));
        if (rmax > worst) worst = rmax, worst_mu = mu;
    }
    if (worst > 1.001f) {
        m_builder.warnings().push_back(m_name + ": " + ptr + ": add reflects " + fmt_number(worst) +
                                       " of the light at cos theta = " + fmt_number(worst_mu) +
                                       " (> 1: an energy gain, allowed as in Cycles' Add Shader)");
    }
}

// Warns for each child of a combination that has a subsurface walk: the walk runs only for
// a material a shape uses directly; inside mix or add the child is its diffuse fallback
// (docs/subsurface.md).
void Builder::check_nested_subsurface(const MaterialDesc& m,
                                      const std::vector<BuiltMaterial>& children,
                                      const std::string& ptr) {
    for (std::size_t k = 0; k < children.size(); ++k) {
        const Material* c = children[k].material;
        if (c == nullptr || c->subsurface() == nullptr) continue;
        m_builder.warnings().push_back(
            m_name + ": " + ptr + "/materials/" + std::to_string(k) +
            ": a subsurface material inside '" + m.model +
            "' renders its diffuse fallback (the random walk runs only for a material a "
            "shape uses directly)");
    }
}

std::string Builder::fmt_number(double v) {
    std::ostringstream s;
    s.precision(3);
    s << v;
    return s.str();
}

// What a texture kind's builder gets (textures/texture_build.h).
class Builder::TextureContext final : public TextureBuild {
  public:
    TextureContext(Builder& b, const TextureDesc& d, const std::string& p, bool c, bool r)
        : TextureBuild(d, p, c, r), m_b(b) {}
    [[noreturn]] void fail(const std::string& p, const std::string& m) const override {
        m_b.fail(p, m);
    }
    bool files_allowed() const override { return m_b.m_limits.allow_files; }
    std::shared_ptr<const TexelImage> load_image(const TexelImageOptions& opt) override {
        return m_b.load_image(desc, opt, ptr);
    }
    std::shared_ptr<const std::vector<TexelImage>> mip_levels(
        const std::shared_ptr<const TexelImage>& img) override {
        try {
            return m_b.m_images.mip_levels(img, ptr + "/texture");
        } catch (const TexelImageError& e) {
            throw SceneError(m_b.m_name + ": " + e.what());
        }
    }
    Texture build_input(const TextureDesc& d, const std::string& p, bool c) override {
        return *m_b.build_texture(d, p, c, false);
    }

  private:
    Builder& m_b;
};

// A texture parameter value (texture.h), validated with JSON pointers under `ptr`. `color`:
// the parameter is a colour (sRGB decoding by default for integer images) or a number
// (linear by default, one channel). `radiance`: negative texels are errors.
const Texture* Builder::build_texture(const TextureDesc& d, const std::string& ptr, bool color,
                                      bool radiance) {
    check_finite(d.scale, ptr + "/scale");
    check_finite(double(d.uv_rotation), ptr + "/uv_rotation");
    for (int i = 0; i < 2; ++i) {
        check_finite(double(d.uv_scale[i]), ptr + "/uv_scale/" + std::to_string(i));
        check_finite(double(d.uv_offset[i]), ptr + "/uv_offset/" + std::to_string(i));
    }
    if (d.scale < 0.0) fail(ptr + "/scale", "must be >= 0");
    check_color(d.color_scale, ptr + "/scale", "a colour multiplier");
    if (!color && (d.color_scale.r != d.color_scale.g || d.color_scale.r != d.color_scale.b))
        fail(ptr + "/scale", "a number parameter needs a number (or grey) scale");
    const TextureKindDef* kind = find_texture_kind(d.kind);
    if (!kind) {
        std::string msg = "unknown texture kind '" + d.kind + "'";
        const std::string g = closest_name(d.kind, texture_kind_names());
        if (!g.empty()) msg += " (did you mean '" + g + "'?)";
        fail(ptr, msg);
    }
    if (!kind->procedural &&
        (!d.params.values().empty() || !d.coordinates.empty() || d.mapping != glm::dmat4(1.0) ||
         !d.inputs.empty() || !d.stops.empty()))
        fail(ptr, "a " + d.kind + " texture has no procedural parameters, coordinates or mapping");
    TextureContext ctx(*this, d, ptr, color, radiance);
    m_builder.textures().push_back(std::make_unique<Texture>(kind->build(ctx)));
    return m_builder.textures().back().get();
}

// Builds a material; parameter errors from the registry name the parameter, which becomes
// part of the pointer. A material with textured parameters also gets its TexturedMaterial:
// the registry validates it with every texture at its smallest and at its largest value
// (a value between them, as bilinear filtering gives, is then valid too).
Builder::BuiltMaterial Builder::build_material(const MaterialDesc& desc, const std::string& ptr,
                                               const MaterialConversion* conversion) {
    MaterialDesc m = desc;
    const Opacity opacity = build_opacity(m, ptr);
    const std::int32_t interior = take_interior(m, ptr);
    BuiltMaterial built = build_model(m, ptr, conversion);
    built.opacity = opacity;
    built.interior = interior;
    // A medium's boundary must let rays in: a transmissive model, or `null`.
    const ModelInfo* info = find_model(m.model);
    const bool pass_through = info && info->pass_through;
    if (interior >= 0 && !pass_through && !built.material->transmissive())
        fail(ptr + "/interior",
             "model '" + m.model +
                 "' cannot bound a medium: rays never cross it (use a transmissive model "
                 "such as dielectric, or \"null\" for an invisible boundary)");
    if (interior >= 0 && opacity.active())
        fail(ptr + "/interior",
             "a medium's boundary cannot be a cut-out (opacity < 1): rays passing through "
             "the holes would not know they entered");
    if (interior >= 0 || pass_through)
        m_builder.interfaces().push_back({built.material, interior, pass_through});
    return built;
}

// The reflection model of a material (build_material without its opacity).
// With a conversion, the parameters and textures are its sources (kind_build.h).
Builder::BuiltMaterial Builder::build_model(const MaterialDesc& m, const std::string& ptr,
                                            const MaterialConversion* conversion) {
    auto to_model = [&](const ParamSet& ps) { return conversion ? conversion->convert(ps) : ps; };
    if (!find_model(m.model)) {
        std::vector<std::string> names;
        for (const auto& mi : model_table()) names.push_back(mi.name);
        std::string msg = "unknown model '" + m.model + "'";
        std::string g = closest_name(m.model, names);
        if (!g.empty()) {
            msg += " (did you mean '" + g + "'?)";
        } else {
            msg += " (expected one of:";
            for (const auto& n : names) msg += " " + n;
            msg += ")";
        }
        fail(ptr + "/model", msg);
    }
    for (const auto& [key, v] : m.params.values()) {
        const std::string p = ptr + "/" + escape_pointer_token(key);
        if (const double* d = std::get_if<double>(&v)) check_finite(*d, p);
        if (const Rgb* c = std::get_if<Rgb>(&v)) check_finite(*c, p);
    }
    // A normal map of strength 0 is no map (exactly: the material stays constant).
    const bool normal_map = m.normal_map && m.normal_map->strength != 0.0;
    if (m.normal_map) {
        check_range(m.normal_map->strength, ptr + "/normal_map/strength", 0.0, 1e6,
                    "in [0, 1e6] (Blender's Normal Map strength; 0 = no map)");
        check_range(m.normal_map->xy_scale, ptr + "/normal_map/xy_scale", -1e6, 1e6,
                    "a finite number (glTF's normalTexture.scale)");
        if (m.normal_map->texture.scale != 1.0)
            fail(ptr + "/normal_map/scale",
                 "a normal map's texels are not scaled: use \"strength\" (Blender) or "
                 "\"xy_scale\" (glTF)");
    }
    if (m.bump) {
        check_range(m.bump->distance, ptr + "/bump/distance", -1e30, 1e30,
                    "a finite number (scene units per unit of height)");
        check_range(m.bump->strength, ptr + "/bump/strength", 0.0, 1e6,
                    "in [0, 1e6] (Blender's Bump strength; 0 = no bump)");
    }
    // A bump of distance 0 or strength 0 is no bump (the material stays constant).
    const bool bump = m.bump && m.bump->distance != 0.0 && m.bump->strength != 0.0;
    const ModelInfo& info = *find_model(m.model);
    const std::vector<BuiltMaterial> children = build_children(m, info, ptr);
    check_nested_subsurface(m, children, ptr);
    std::vector<std::shared_ptr<const Material>> kids;
    bool textured_child = false;
    for (const BuiltMaterial& c : children) {
        kids.push_back(c.shared);
        textured_child = textured_child || c.textured >= 0;
    }
    if (m.textures.empty() && !normal_map && !bump && !textured_child) {
        try {
            m_builder.materials().push_back(
                std::make_shared<Material>(make_material(m.model, to_model(m.params), kids)));
        } catch (const ParamError& e) {
            fail(e.param().empty() ? ptr + "/model" : ptr + "/" + escape_pointer_token(e.param()),
                 e.what());
        }
        check_energy_gain(m, *m_builder.materials().back(), ptr);
        return {m_builder.materials().back().get(), -1, m_builder.materials().back()};
    }
    const std::vector<ParamInfo>& table =
        conversion ? conversion->sources : find_model(m.model)->params;
    TexturedMaterial tm;
    tm.model = m.model;
    tm.params = m.params;
    if (conversion) tm.convert = conversion->convert;
    for (const BuiltMaterial& c : children)
        tm.children.push_back({c.textured >= 0 ? nullptr : c.shared, c.textured});
    for (const auto& [name, td] : m.textures) {
        const std::string& key = name;  // (clang 14 cannot capture a structured binding)
        const std::string p = ptr + "/" + escape_pointer_token(key);
        if (m.params.has(key)) fail(p, "given both as a constant and as a texture");
        const auto pi = std::find_if(table.begin(), table.end(),
                                     [&](const ParamInfo& x) { return x.name == key; });
        if (pi == table.end()) {
            std::vector<std::string> names;
            for (const auto& x : table) names.push_back(x.name);
            std::string msg = "unknown parameter '" + key + "' for model '" + m.model + "'";
            const std::string g = closest_name(key, names);
            if (!g.empty()) msg += " (did you mean '" + g + "'?)";
            fail(p, msg);
        }
        if (pi->type != ParamType::Color && pi->type != ParamType::Number)
            fail(p, "only colour and number parameters can be textures");
        const bool color = pi->type == ParamType::Color;
        tm.slots.push_back({key, build_texture(td, p, color, false), color});
        tm.uses_uv = tm.uses_uv || tm.slots.back().texture->uses_uv();
        tm.uses_color = tm.uses_color || tm.slots.back().texture->uses_vertex_color();
        tm.uses_position = tm.uses_position || tm.slots.back().texture->uses_position();
        tm.uses_view = tm.uses_view || tm.slots.back().texture->uses_view();
        tm.uses_strand = tm.uses_strand || tm.slots.back().texture->uses_strand();
        tm.uses_ray = tm.uses_ray || tm.slots.back().texture->uses_ray();
    }
    for (const BuiltMaterial& c : children) {
        if (c.textured < 0) continue;
        const TexturedMaterial& ct = m_builder.textured()[std::size_t(c.textured)];
        tm.uses_uv = tm.uses_uv || ct.uses_uv;
        tm.uses_color = tm.uses_color || ct.uses_color;
        tm.uses_position = tm.uses_position || ct.uses_position;
        tm.uses_view = tm.uses_view || ct.uses_view;
        tm.uses_strand = tm.uses_strand || ct.uses_strand;
        tm.uses_ray = tm.uses_ray || ct.uses_ray;
    }
    // Validate at the extremes: slot i at its largest value when bit i of `corner` is set.
    // The model's own parameters are checked per value (both ends); a conversion mixes its
    // sources, monotonically in each (glTF: b (1 - m), r^2, ...), so every corner of the
    // box. Keep the material of the largest values for the analysis, and every corner's
    // lobes (TexturedMaterial::flags).
    auto with = [&](std::uint32_t corner) {
        ParamSet ps = tm.params;
        for (std::size_t i = 0; i < tm.slots.size(); ++i) {
            const auto& s = tm.slots[i];
            const Rgb v = (corner >> i) & 1u ? s.texture->max_value() : s.texture->min_value();
            ps.set(s.name, s.color ? ParamValue(v) : ParamValue(double(v.r)));
        }
        return ps;
    };
    if (tm.slots.size() > TexturedMaterial::kMaxStaged)
        fail(ptr,
             "more than " + std::to_string(TexturedMaterial::kMaxStaged) + " textured parameters");
    const std::uint32_t all = (1u << tm.slots.size()) - 1u;
    std::vector<std::uint32_t> corners{0u, all};
    if (conversion) {
        if (tm.slots.size() > 8) fail(ptr, "more than 8 textured sources");
        corners.clear();
        for (std::uint32_t c = 0; c <= all; ++c) corners.push_back(c);
    }
    for (std::uint32_t corner : corners) {
        const bool largest = corner == all;
        try {
            // Children: their largest-value materials (the analysis' view of them).
            Material mat = make_material(m.model, to_model(with(corner)), kids);
            tm.flags = tm.flags | mat.flags();
            if (largest) m_builder.materials().push_back(std::make_shared<Material>(mat));
        } catch (const ParamError& e) {
            fail(e.param().empty() ? ptr + "/model" : ptr + "/" + escape_pointer_token(e.param()),
                 std::string(e.what()) + " (a texture's " +
                     (largest       ? "largest"
                      : corner == 0 ? "smallest"
                                    : "extreme") +
                     " value)");
        }
    }
    stage(tm, *m_builder.materials().back(), conversion);
    if (!tm.staged)
        fail(ptr, "model '" + m.model +
                      "': its textured parameters have no per-hit build (a conversion without "
                      "convert_values or a source without a numeric default)");
    for (const auto& s : tm.slots)
        tm.params.set(s.name, s.color ? ParamValue(Rgb(0.f)) : ParamValue(0.0));
    for (const auto* map :
         {m.normal_map ? &m.normal_map->texture : nullptr, m.bump ? &m.bump->texture : nullptr}) {
        if (map && (map->kind == "vertex_color" || map->times_vertex_color))
            fail(ptr + (map == &m.bump->texture ? "/bump" : "/normal_map"),
                 "a vertex colour cannot be a normal or bump map (they need texture "
                 "coordinates)");
    }
    tm.uses_uv = tm.uses_uv || normal_map || bump;
    if (normal_map) {
        // Read linearly unless the scene says otherwise (the texture's colour space key).
        TextureDesc td = m.normal_map->texture;
        if (td.colorspace.empty()) td.colorspace = "linear";
        tm.normal_map = build_texture(td, ptr + "/normal_map", true, false);
        if (tm.normal_map->uses_position() || tm.normal_map->uses_view() ||
            tm.normal_map->uses_strand() || tm.normal_map->uses_ray())
            fail(ptr + "/normal_map",
                 "a normal map reads UVs only: give the procedural texture "
                 "\"coordinates\": \"uv\"");
        tm.normal_strength = float(m.normal_map->strength);
        tm.normal_xy_scale = float(m.normal_map->xy_scale);
    }
    if (bump) {
        tm.bump = build_texture(m.bump->texture, ptr + "/bump", false, false);
        if (tm.bump->uses_position() || tm.bump->uses_view() || tm.bump->uses_strand() ||
            tm.bump->uses_ray())
            fail(ptr + "/bump",
                 "a bump map reads UVs only: give the procedural texture \"coordinates\": "
                 "\"uv\"");
        tm.bump_distance = float(m.bump->distance);
        tm.bump_strength = float(m.bump->strength);
        // Forward-difference step in uv: half a texel of the image (or a thousandth of a
        // checker cell), through the texture's UV scale.
        const TextureDesc& td = m.bump->texture;
        const double per_uv =
            std::max({std::fabs(double(td.uv_scale.x)), std::fabs(double(td.uv_scale.y)), 1e-12});
        const TexelImage* im = tm.bump->texel_image();
        const double cells =
            im ? double(std::max(im->width, im->height)) : 1000.0 * td.checker_scale;
        tm.bump_step = float(0.5 / (cells * per_uv));
    }
    // A texture on the diffuse reflectance alone of a model with that Lambert lobe
    // (ModelInfo::diffuse_lobe): only the lobe's rho changes per hit.
    if (!tm.convert && tm.slots.size() == 1 && info.diffuse_lobe &&
        tm.slots[0].name == info.diffuse_param && m_builder.materials().back()->diffuse()) {
        tm.diffuse_base = m_builder.materials().back().get();
        tm.diffuse_black_ok = info.diffuse_black_ok;
    }
    m_builder.textured().push_back(std::move(tm));
    return {m_builder.materials().back().get(), std::int32_t(m_builder.textured().size() - 1),
            m_builder.materials().back()};
}

// The staged per-hit build of a textured material (facet/staged_material.h); left null where a
// conversion cannot be staged (build_model's error). `base` is the material at the textures'
// largest values (with a conversion: its sources' largest), validated by build_model.
void Builder::stage(TexturedMaterial& tm, const Material& base,
                    const MaterialConversion* conversion) {
    using Range = StagedMaterial::Range;
    constexpr std::size_t kMax = TexturedMaterial::kMaxStaged;
    auto value = [](const TexturedMaterial::Slot& s, const Rgb& v) {
        return s.color ? DVec3(v) : DVec3(double(v.r));
    };
    // The parameters `base` was built from (build_model: every slot at its largest value).
    ParamSet params = tm.params;
    for (const TexturedMaterial::Slot& s : tm.slots)
        params.set(s.name, s.color ? ParamValue(s.texture->max_value())
                                   : ParamValue(double(s.texture->max_value().r)));
    if (conversion) params = conversion->convert(params);
    std::vector<std::string> names;
    std::vector<Range> ranges;
    if (tm.slots.size() > kMax) return;
    if (!conversion) {
        for (const TexturedMaterial::Slot& s : tm.slots) {
            names.push_back(s.name);
            ranges.push_back({value(s, s.texture->min_value()), value(s, s.texture->max_value())});
        }
    } else {
        if (!conversion->convert_values || conversion->sources.size() > kMax ||
            conversion->outputs.size() > kMax)
            return;
        // The sources' constants, and the source of each slot.
        tm.sources.assign(conversion->sources.size(), DVec3(0.0));
        tm.slot_source.assign(tm.slots.size(), 0);
        for (std::size_t i = 0; i < conversion->sources.size(); ++i) {
            const std::string& name = conversion->sources[i].name;
            const auto slot = std::find_if(tm.slots.begin(), tm.slots.end(),
                                           [&](const auto& s) { return s.name == name; });
            if (slot != tm.slots.end()) {
                tm.slot_source[std::size_t(slot - tm.slots.begin())] = std::uint8_t(i);
                continue;
            }
            if (!tm.params.has(name)) {
                // A default: its documented value (ParamInfo::default_value, one number or
                // three).
                std::istringstream text(conversion->sources[i].default_value);
                double x[3];
                int n = 0;
                while (n < 3 && text >> x[n]) ++n;
                if (n == 1) tm.sources[i] = DVec3(x[0]);
                if (n == 3) tm.sources[i] = DVec3(x[0], x[1], x[2]);
                if (n != 1 && n != 3) return;
                continue;
            }
            const ParamValue& v = tm.params.values().at(name);
            if (const double* d = std::get_if<double>(&v))
                tm.sources[i] = DVec3(*d);
            else if (const Rgb* c = std::get_if<Rgb>(&v))
                tm.sources[i] = DVec3(*c);
            else
                return;
        }
        // The outputs' ranges: over every corner of the sources' box (the conversion is
        // monotonic in each source, as build_model's validation assumes).
        names = conversion->outputs;
        ranges.assign(names.size(), {DVec3(INFINITY), DVec3(-INFINITY)});
        std::vector<DVec3> src(tm.sources), out(names.size());
        for (std::uint32_t c = 0; c < (1u << tm.slots.size()); ++c) {
            for (std::size_t i = 0; i < tm.slots.size(); ++i) {
                const auto& s = tm.slots[i];
                src[tm.slot_source[i]] =
                    value(s, (c >> i) & 1u ? s.texture->max_value() : s.texture->min_value());
            }
            conversion->convert_values(src.data(), out.data());
            for (std::size_t k = 0; k < out.size(); ++k) {
                ranges[k].lo = glm::min(ranges[k].lo, out[k]);
                ranges[k].hi = glm::max(ranges[k].hi, out[k]);
            }
        }
        tm.convert_values = conversion->convert_values;
    }
    std::optional<StagedMaterial> st = StagedMaterial::make(tm.model, base, params, names, ranges);
    if (!st) {
        tm.sources.clear(), tm.slot_source.clear(), tm.convert_values = nullptr;
        return;
    }
    tm.staged = std::make_shared<const StagedMaterial>(std::move(*st));
    tm.num_staged = names.size();
}

void Builder::build_materials() {
    for (const auto& [name, m] : m_desc.materials) {
        const std::string ptr = "/materials/" + escape_pointer_token(name);
        if (m_named_desc.count(name)) fail(ptr, "duplicate material name '" + name + "'");
        m_named_desc[name] = &m;
    }
    for (const auto& [name, m] : m_desc.materials)
        named_material(name, "/materials/" + escape_pointer_token(name));
}

const Material* Builder::black_material() {
    if (!m_black) {
        m_builder.materials().push_back(
            std::make_unique<Material>(std::nullopt, std::nullopt, std::nullopt));
        m_black = m_builder.materials().back().get();
    }
    return m_black;
}

}  // namespace facet::render::detail
