// What the composite texture kinds share (composite.h).
#include "composite.h"

#include <sstream>

namespace facet::render {

CompositeParams::CompositeParams(TextureBuild& b, const TextureKindDef& kind)
    : ProceduralParams(b, kind), m_b(b), m_kind(kind) {}

CompositeInput CompositeParams::input(std::string_view name, bool color) const {
    CompositeInput in;
    const TextureDesc& d = m_b.desc;
    const std::string p = pointer(name);
    for (const TextureInputDesc& x : d.inputs) {
        if (x.name != name) continue;
        in.m_texture = m_b.build_input(x.texture, p, color);
        in.m_lo = in.m_texture->min_value();
        in.m_hi = in.m_texture->max_value();
        m_reads |= in.m_texture->inputs();
        return in;
    }
    const TextureParamDef* def = find_texture_param(m_kind, name);
    const auto it = d.params.values().find(std::string(name));
    if (it == d.params.values().end()) {
        in.m_constant = def && def->type == ParamType::Color ? def->default_color
                        : def                                ? Rgb(float(def->default_number))
                                                             : Rgb(0.f);
    } else if (const Rgb* c = std::get_if<Rgb>(&it->second)) {
        if (!color && (c->r != c->g || c->r != c->b))
            m_b.fail(p,
                     "a number is needed here (the texture feeds a number): give a number or "
                     "a grey colour");
        in.m_constant = *c;
    } else {
        in.m_constant = Rgb(float(std::get<double>(it->second)));
    }
    in.m_lo = in.m_hi = in.m_constant;
    return in;
}

namespace {

std::string fmt(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

}  // namespace

Texture make_composite(TextureBuild& b, const TextureKindDef& kind,
                       std::shared_ptr<CompositeSource> s, Rgb lo, Rgb hi, unsigned reads,
                       const std::string& why) {
    const TextureDesc& d = b.desc;
    if (!d.coordinates.empty())
        b.fail(b.ptr + "/coordinates",
               "a " + std::string(kind.name) +
                   " texture reads no point of its own (give its inputs' textures coordinates)");
    if (d.mapping != glm::dmat4(1.0))
        b.fail(b.ptr + "/mapping", "a " + std::string(kind.name) +
                                       " texture reads no point of its own (give its inputs' "
                                       "textures a mapping)");
    for (int c = 0; c < 3; ++c) {
        if (!std::isfinite(lo[c]) || !std::isfinite(hi[c]))
            b.fail(b.ptr + "/" + std::string(kind.name),
                   "the texture's values cannot be bounded (" + why + ", range [" +
                       fmt(double(lo[c])) + ", " + fmt(double(hi[c])) +
                       "]): bound its inputs or clamp the result");
    }
    if (!b.color && d.channel.empty() &&
        (lo.r != lo.g || lo.r != lo.b || hi.r != hi.g || hi.r != hi.b))
        b.fail(b.ptr + "/" + std::string(kind.name),
               "a number parameter needs a grey value (this texture gives a colour; or give "
               "\"channel\")");
    const Rgb scale = float(d.scale) * d.color_scale;
    s->m_scale = scale;
    return with_channel(b, Texture(std::move(s), lo * scale, hi * scale, reads));
}

}  // namespace facet::render
