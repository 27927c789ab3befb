// What the procedural texture kinds share (procedural.h).
#include "procedural.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace facet::render {

namespace {

std::string fmt_param(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

}  // namespace

std::string ProceduralParams::pointer(std::string_view name) const {
    return m_b.ptr + "/" + std::string(m_kind.name) + "/" + std::string(name);
}

double ProceduralParams::number(std::string_view name) const {
    const TextureParamDef* def = find_texture_param(m_kind, name);
    const auto& values = m_b.desc.params.values();
    const auto it = values.find(std::string(name));
    if (it == values.end() || !def) return def ? def->default_number : 0.0;
    return std::get<double>(it->second);  // checked by check_texture_params
}

int ProceduralParams::choice(std::string_view name) const {
    const TextureParamDef* def = find_texture_param(m_kind, name);
    if (!def) return 0;
    const auto& values = m_b.desc.params.values();
    const auto it = values.find(std::string(name));
    const std::string v =
        it == values.end() ? std::string(def->default_text) : std::get<std::string>(it->second);
    return m_b.choose(std::string(m_kind.name) + "/" + std::string(name), v, def->choices);
}

bool ProceduralParams::flag(std::string_view name) const {
    const TextureParamDef* def = find_texture_param(m_kind, name);
    const auto& values = m_b.desc.params.values();
    const auto it = values.find(std::string(name));
    if (it == values.end() || !def) return def ? def->default_number != 0.0 : false;
    return std::get<bool>(it->second);  // checked by check_texture_params
}

Rgb ProceduralParams::color(std::string_view name) const {
    const TextureParamDef* def = find_texture_param(m_kind, name);
    const auto& values = m_b.desc.params.values();
    const auto it = values.find(std::string(name));
    if (it == values.end() || !def) return def ? def->default_color : Rgb(0.f);
    if (const Rgb* c = std::get_if<Rgb>(&it->second)) return *c;
    return Rgb(float(std::get<double>(it->second)));  // checked by check_texture_params
}

void check_texture_params(TextureBuild& b, const TextureKindDef& kind) {
    const TextureDesc& d = b.desc;
    ProceduralParams params(b, kind);
    auto find_def = [&](const std::string& name, const std::string& p) {
        const TextureParamDef* def = find_texture_param(kind, name);
        if (def) return def;
        std::vector<std::string> names;
        for (const TextureParamDef& x : kind.params) names.emplace_back(x.name);
        std::string msg =
            "unknown parameter '" + name + "' of a " + std::string(kind.name) + " texture";
        const std::string g = closest_name(name, names);
        if (!g.empty()) msg += " (did you mean '" + g + "'?)";
        b.fail(p, msg);
    };
    for (const auto& [name, value] : d.params.values()) {
        const std::string p = params.pointer(name);
        const TextureParamDef* def = find_def(name, p);
        if (def->form == TextureParamForm::Stops) b.fail(p, "expected a list of stops");
        const bool input = def->form == TextureParamForm::Input;
        if (def->type == ParamType::Number || def->type == ParamType::Color) {
            if (const Rgb* c = std::get_if<Rgb>(&value); c && def->type == ParamType::Color) {
                for (int i = 0; i < 3; ++i)
                    b.check_finite(double((*c)[i]), p + "/" + std::to_string(i));
                continue;
            }
            const double* v = std::get_if<double>(&value);
            if (!v)
                b.fail(p, def->type == ParamType::Color
                              ? (input ? "expected a colour [r, g, b], a number or a texture"
                                       : "expected a colour [r, g, b] or a number")
                          : input ? "expected a number or a texture"
                                  : "expected a number");
            b.check_finite(*v, p);
            if (def->type == ParamType::Number && !(*v >= def->lo && *v <= def->hi)) {
                std::string range = "in [" + fmt_param(def->lo) + ", " + fmt_param(def->hi) + "]";
                b.fail(p, detail::number_range_message(*v, range.c_str()));
            }
            if (def->integer && std::floor(*v) != *v) b.fail(p, "must be an integer");
        } else if (def->type == ParamType::Bool) {
            if (!std::get_if<bool>(&value)) b.fail(p, "expected true or false");
        } else {
            if (!std::get_if<std::string>(&value)) b.fail(p, "expected a name");
            params.choice(name);
        }
    }
    for (const TextureInputDesc& in : d.inputs) {
        const std::string p = params.pointer(in.name);
        const TextureParamDef* def = find_def(in.name, p);
        if (def->form != TextureParamForm::Input)
            b.fail(p, "'" + in.name + "' cannot be a texture (a constant only)");
        if (d.params.has(in.name)) b.fail(p, "given both as a constant and as a texture");
    }
    bool has_stops = false;
    for (const TextureParamDef& def : kind.params)
        has_stops = has_stops || def.form == TextureParamForm::Stops;
    if (!has_stops && !d.stops.empty())
        b.fail(b.ptr + "/" + std::string(kind.name) + "/stops",
               "a " + std::string(kind.name) + " texture has no stops");
    for (std::size_t i = 0; i < d.stops.size(); ++i) {
        const std::string p = b.ptr + "/" + std::string(kind.name) + "/stops/" + std::to_string(i);
        const TextureStop& s = d.stops[i];
        b.check_finite(s.position, p + "/position");
        if (!(s.position >= 0.0 && s.position <= 1.0))
            b.fail(p + "/position", detail::number_range_message(s.position, "in [0, 1]"));
        if (i > 0 && s.position < d.stops[i - 1].position)
            b.fail(p + "/position", "the stops must be in order of position (this one, " +
                                        fmt_param(s.position) + ", comes before the previous, " +
                                        fmt_param(d.stops[i - 1].position) + ")");
        for (int c = 0; c < 4; ++c) b.check_finite(s.color[c], p + "/color/" + std::to_string(c));
    }
}

Texture make_procedural(TextureBuild& b, const TextureKindDef& kind,
                        std::shared_ptr<ProceduralSource> s, Rgb lo, Rgb hi, unsigned reads) {
    const TextureDesc& d = b.desc;
    ProceduralParams params(b, kind);
    check_texture_params(b, kind);
    if (d.coordinates.empty() || d.coordinates == "generated") {
        s->m_coordinates = ProceduralSource::Coordinates::Generated;
    } else {
        const int c = b.choose("coordinates", d.coordinates, kCoordinateNames);
        s->m_coordinates = ProceduralSource::Coordinates(c);
    }
    const std::string mp = b.ptr + "/mapping";
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 3; ++r) b.check_finite(d.mapping[c][r], mp);
    if (d.mapping[0][3] != 0.0 || d.mapping[1][3] != 0.0 || d.mapping[2][3] != 0.0 ||
        d.mapping[3][3] != 1.0)
        b.fail(mp, "the last row must be [0, 0, 0, 1] (affine maps only)");
    s->m_linear = glm::mat3(glm::dmat3(d.mapping));
    s->m_offset = Vec3(glm::dvec3(d.mapping[3]));
    s->m_scale = float(d.scale) * d.color_scale;
    // A colour output (not a grey one) read by a number parameter needs a channel.
    bool colour_output = false;
    if (const TextureParamDef* out = find_texture_param(kind, "output"); out && !kind.grey_color) {
        const auto c = std::find(out->choices.begin(), out->choices.end(), "color");
        colour_output =
            c != out->choices.end() && params.choice("output") == c - out->choices.begin();
    }
    if (!b.color && d.channel.empty() &&
        (colour_output || lo.r != lo.g || lo.r != lo.b || hi.r != hi.g || hi.r != hi.b))
        b.fail(params.pointer("output"),
               "a number parameter needs a grey output (a colour output feeds colours; or give "
               "\"channel\")");
    using C = ProceduralSource::Coordinates;
    unsigned inputs = s->m_coordinates == C::Uv ? kTextureReadsUv
                      : s->m_coordinates == C::Generated || s->m_coordinates == C::Object
                          ? kTextureReadsPosition
                          : kTextureReadsView;
    inputs |= reads;
    return with_channel(b, Texture(std::move(s), lo * (float(d.scale) * d.color_scale),
                                   hi * (float(d.scale) * d.color_scale), inputs));
}

namespace {

// One channel (or the luminance) of a procedural or composite texture's colour, as grey.
class ChannelSource final : public TextureSource {
  public:
    ChannelSource(Texture t, int channel) : m_texture(std::move(t)), m_channel(channel) {}
    Rgb eval(const TexturePoint& p) const override { return Rgb(pick(m_texture.eval(p))); }
    float pick(const Rgb& v) const {
        return m_channel == Texture::kLuminance ? 0.2126f * v.r + 0.7152f * v.g + 0.0722f * v.b
                                                : v[m_channel];
    }

    Texture m_texture;
    int m_channel;
};

}  // namespace

Texture with_channel(TextureBuild& b, Texture t) {
    if (b.desc.channel.empty()) return t;
    int c = b.choose("channel", b.desc.channel, {"r", "g", "b", "luminance"});
    if (c == 3) c = Texture::kLuminance;
    auto s = std::make_shared<ChannelSource>(t, c);
    // The weights are >= 0: the luminance of the range's ends bounds the luminance.
    const Rgb lo(s->pick(t.min_value())), hi(s->pick(t.max_value()));
    return Texture(std::move(s), lo, hi, t.inputs());
}

namespace {

// Builds outside a scene: no images, errors as std::invalid_argument.
class StandaloneBuild final : public TextureBuild {
  public:
    using TextureBuild::TextureBuild;
    [[noreturn]] void fail(const std::string& p, const std::string& m) const override {
        throw std::invalid_argument(p + ": " + m);
    }
    bool files_allowed() const override { return false; }
    std::shared_ptr<const TexelImage> load_image(const TexelImageOptions&) override {
        fail(ptr, "no images outside a scene");
    }
    std::shared_ptr<const std::vector<TexelImage>> mip_levels(
        const std::shared_ptr<const TexelImage>&) override {
        fail(ptr, "no images outside a scene");
    }
    Texture build_input(const TextureDesc& d, const std::string& p, bool c) override {
        const TextureKindDef* kind = find_texture_kind(d.kind);
        if (!kind || !kind->procedural)
            fail(p, "'" + d.kind + "' is no procedural texture kind (outside a scene)");
        if (d.scale < 0.0) fail(p + "/scale", "must be >= 0");
        StandaloneBuild sub(d, p, c, false);
        return kind->build(sub);
    }
};

}  // namespace

Texture build_procedural_texture(const TextureDesc& desc, bool color, const std::string& ptr) {
    const TextureKindDef* kind = find_texture_kind(desc.kind);
    if (!kind || !kind->procedural)
        throw std::invalid_argument(ptr + ": '" + desc.kind + "' is no procedural texture kind");
    StandaloneBuild b(desc, ptr, color, false);
    return kind->build(b);
}

const TextureParamDef* find_texture_param(const TextureKindDef& kind, std::string_view name) {
    for (const TextureParamDef& p : kind.params)
        if (p.name == name) return &p;
    return nullptr;
}

}  // namespace facet::render
