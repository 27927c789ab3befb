// Texture kind "mix_rgb": Blender 3.4's Mix RGB node (and the Mix node's Color mode) evaluated
// per hit (Cycles' svm_mix, in float, per channel with t = fac, a = color1, b = color2):
// mix a + t (b - a); add a + t b; multiply a + t (a b - a); subtract a - t b; screen
// 1 - (1 - t + t (1 - b)) (1 - a); divide (1 - t) a + t a / b (channels with b = 0 keep a);
// difference a + t (|a - b| - a); darken / lighten a + t (min / max(a, b) - a); overlay
// a (1 - t + 2 t b) for a < 1/2, else 1 - (1 - t + 2 t (1 - b)) (1 - a); dodge a / (1 - t b)
// capped at 1 (1 when 1 - t b <= 0, a when a = 0); burn 1 - (1 - a) / (1 - t + t b) clamped to
// [0, 1] (0 when the divisor is <= 0); soft light (1 - t) a + t ((1 - a) b a + a s), s = 1 -
// (1 - b)(1 - a); linear light a + t (2 b - 1); hue, saturation, value and color through
// Cycles' rgb_to_hsv / hsv_to_rgb (hue: a's HSV with b's hue, mixed by t, when b has
// saturation; saturation: a's saturation mixed toward b's when a has some; value: a's value
// mixed toward b's; color: b's hue and saturation, mixed by t, when b has saturation). `fac`
// is clamped to [0, 1] first when `clamp_factor` (always, for the Mix RGB node), the result to
// [0, 1] when `use_clamp`. `fac_color` (blend `mix` only) replaces `fac` by one factor per
// channel: the Mix node's Vector mode with a Non-Uniform factor (Cycles'
// svm_node_mix_vector_non_uniform, a + t (b - a) per component).
#include <algorithm>
#include <array>
#include <cmath>

#include "composite.h"

namespace facet::render {

namespace {

enum class Blend {
    Mix,
    Darken,
    Multiply,
    Burn,
    Lighten,
    Screen,
    Dodge,
    Add,
    Overlay,
    SoftLight,
    LinearLight,
    Difference,
    Subtract,
    Divide,
    Hue,
    Saturation,
    Color,
    Value,
};

const std::vector<std::string> kBlends = {
    "mix",      "darken", "multiply", "burn",       "lighten",      "screen",
    "dodge",    "add",    "overlay",  "soft_light", "linear_light", "difference",
    "subtract", "divide", "hue",      "saturation", "color",        "value",
};

// Cycles' rgb_to_hsv and hsv_to_rgb (util/color.h).
Rgb rgb_to_hsv(const Rgb& c) {
    const float cmax = std::fmax(c.r, std::fmax(c.g, c.b));
    const float cmin = std::fmin(c.r, std::fmin(c.g, c.b));
    const float cdelta = cmax - cmin;
    const float v = cmax;
    const float s = cmax != 0.f ? cdelta / cmax : 0.f;
    float h = 0.f;
    if (s != 0.f) {
        const Rgb d = (Rgb(cmax) - c) / cdelta;
        if (c.r == cmax)
            h = d.b - d.g;
        else if (c.g == cmax)
            h = 2.f + d.r - d.b;
        else
            h = 4.f + d.g - d.r;
        h /= 6.f;
        if (h < 0.f) h += 1.f;
    }
    return {h, s, v};
}

Rgb hsv_to_rgb(const Rgb& hsv) {
    float h = hsv.x;
    const float s = hsv.y, v = hsv.z;
    if (s == 0.f) return Rgb(v);
    if (h == 1.f) h = 0.f;
    h *= 6.f;
    const float i = std::floor(h), f = h - i;
    const float p = v * (1.f - s), q = v * (1.f - s * f), t = v * (1.f - s * (1.f - f));
    if (i == 0.f) return {v, t, p};
    if (i == 1.f) return {q, v, p};
    if (i == 2.f) return {p, v, t};
    if (i == 3.f) return {p, q, v};
    if (i == 4.f) return {t, p, v};
    return {v, p, q};
}

Rgb interp(const Rgb& a, const Rgb& b, float t) {
    return a + t * (b - a);
}

// Cycles' svm_mix.
Rgb mix(Blend type, float t, const Rgb& a, const Rgb& b) {
    const float tm = 1.f - t;
    Rgb o = a;
    switch (type) {
        case Blend::Mix:
            return interp(a, b, t);
        case Blend::Add:
            return interp(a, a + b, t);
        case Blend::Multiply:
            return interp(a, a * b, t);
        case Blend::Subtract:
            return interp(a, a - b, t);
        case Blend::Screen:
            return Rgb(1.f) - (Rgb(tm) + t * (Rgb(1.f) - b)) * (Rgb(1.f) - a);
        case Blend::Divide:
            for (int c = 0; c < 3; ++c)
                if (b[c] != 0.f) o[c] = tm * a[c] + t * a[c] / b[c];
            return o;
        case Blend::Difference:
            return interp(a, glm::abs(a - b), t);
        case Blend::Darken:
            return interp(a, glm::min(a, b), t);
        case Blend::Lighten:
            return interp(a, glm::max(a, b), t);
        case Blend::Overlay:
            for (int c = 0; c < 3; ++c)
                o[c] = a[c] < 0.5f ? a[c] * (tm + 2.f * t * b[c])
                                   : 1.f - (tm + 2.f * t * (1.f - b[c])) * (1.f - a[c]);
            return o;
        case Blend::Dodge:
            for (int c = 0; c < 3; ++c) {
                if (o[c] == 0.f) continue;
                const float tmp = 1.f - t * b[c];
                o[c] = tmp <= 0.f ? 1.f : std::fmin(o[c] / tmp, 1.f);
            }
            return o;
        case Blend::Burn:
            for (int c = 0; c < 3; ++c) {
                float tmp = tm + t * b[c];
                if (tmp <= 0.f) {
                    o[c] = 0.f;
                } else {
                    tmp = 1.f - (1.f - o[c]) / tmp;
                    o[c] = tmp < 0.f ? 0.f : tmp > 1.f ? 1.f : tmp;
                }
            }
            return o;
        case Blend::Hue: {
            const Rgb hsv2 = rgb_to_hsv(b);
            if (hsv2.y == 0.f) return a;
            Rgb hsv = rgb_to_hsv(a);
            hsv.x = hsv2.x;
            return interp(a, hsv_to_rgb(hsv), t);
        }
        case Blend::Saturation: {
            Rgb hsv = rgb_to_hsv(a);
            if (hsv.y == 0.f) return a;
            hsv.y = tm * hsv.y + t * rgb_to_hsv(b).y;
            return hsv_to_rgb(hsv);
        }
        case Blend::Value: {
            Rgb hsv = rgb_to_hsv(a);
            hsv.z = tm * hsv.z + t * rgb_to_hsv(b).z;
            return hsv_to_rgb(hsv);
        }
        case Blend::Color: {
            const Rgb hsv2 = rgb_to_hsv(b);
            if (hsv2.y == 0.f) return a;
            Rgb hsv = rgb_to_hsv(a);
            hsv.x = hsv2.x;
            hsv.y = hsv2.y;
            return interp(a, hsv_to_rgb(hsv), t);
        }
        case Blend::SoftLight: {
            const Rgb one(1.f);
            const Rgb scr = one - (one - b) * (one - a);
            return tm * a + t * ((one - a) * b * a + a * scr);
        }
        case Blend::LinearLight:
            return a + t * (2.f * b - Rgb(1.f));
    }
    return Rgb(0.f);
}

constexpr Interval kAll{-INFINITY, INFINITY};

// The hull of f over the corners of the box x × y × z (f multilinear: exact).
template <class F>
Interval corners(Interval x, Interval y, Interval z, F f) {
    Interval r{INFINITY, -INFINITY};
    for (double u : {x.lo, x.hi})
        for (double v : {y.lo, y.hi})
            for (double w : {z.lo, z.hi}) r = r.join(Interval::of(f(u, v, w)));
    return r;
}

// A conservative range of one channel of mix(type, t, a, b) (composite.h); `all_a`, `all_b`:
// the hulls of the inputs' channels (the HSV blends mix across channels).
Interval mix_range(Blend type, Interval t, Interval a, Interval b, Interval all_a, Interval all_b) {
    auto lerp = [](double t, double x, double y) { return x + t * (y - x); };
    switch (type) {
        case Blend::Mix:
            return corners(t, a, b, lerp);
        case Blend::Add:
            return corners(t, a, b, [](double t, double x, double y) { return x + t * y; });
        case Blend::Multiply:
            return corners(t, a, b,
                           [](double t, double x, double y) { return x + t * (x * y - x); });
        case Blend::Subtract:
            return corners(t, a, b, [](double t, double x, double y) { return x - t * y; });
        case Blend::Screen:
            return corners(t, a, b, [](double t, double x, double y) {
                return 1.0 - (1.0 - t * y) * (1.0 - x);
            });
        case Blend::Divide: {
            if (b.lo == 0.0 && b.hi == 0.0) return a;
            if (b.contains(0.0)) return kAll;
            const Interval inv{1.0 / b.hi, 1.0 / b.lo};
            return corners(t, a, inv,
                           [](double t, double x, double r) { return (1.0 - t) * x + t * x * r; });
        }
        case Blend::Difference: {
            const Interval d = (a - b).lo >= 0.0 ? a - b
                               : (a - b).hi <= 0.0
                                   ? b - a
                                   : Interval{0.0, std::max(-(a - b).lo, (a - b).hi)};
            return corners(t, a, d, lerp);
        }
        case Blend::Darken:
            return corners(t, a, Interval{std::min(a.lo, b.lo), std::min(a.hi, b.hi)}, lerp);
        case Blend::Lighten:
            return corners(t, a, Interval{std::max(a.lo, b.lo), std::max(a.hi, b.hi)}, lerp);
        case Blend::Overlay:
            return corners(t, a, b,
                           [](double t, double x, double y) { return x * (1.0 - t + 2.0 * t * y); })
                .join(corners(t, a, b, [](double t, double x, double y) {
                    return 1.0 - (1.0 - t + 2.0 * t * (1.0 - y)) * (1.0 - x);
                }));
        case Blend::Dodge: {
            if (a.lo >= 0.0) return {0.0, 1.0};  // 0 (a = 0), 1, or a / tmp in (0, 1]
            const Interval tmp = Interval::of(1.0) - t * b;
            if (!(tmp.lo > 0.0)) return kAll;
            const Interval q = a * Interval{1.0 / tmp.hi, 1.0 / tmp.lo};
            return Interval{std::min(q.lo, 1.0), std::min(q.hi, 1.0)}.join(Interval::of(0.0));
        }
        case Blend::Burn:
            return {0.0, 1.0};
        case Blend::SoftLight: {
            const Interval one = Interval::of(1.0);
            const Interval s = (one - t) * a + t * (a * a + Interval::of(2.0) * a * b -
                                                    Interval::of(2.0) * a * a * b);
            return s;
        }
        case Blend::LinearLight:
            return corners(t, a, b,
                           [](double t, double x, double y) { return x + t * (2.0 * y - 1.0); });
        case Blend::Hue:
        case Blend::Saturation:
        case Blend::Value:
        case Blend::Color: {
            // Non-negative colours: HSV saturation in [0, 1], value the largest channel.
            if (all_a.lo < 0.0 || all_b.lo < 0.0) return kAll;
            const Interval v{0.0, std::max(all_a.hi, all_b.hi)};
            const Interval unit{0.0, 1.0};
            if (type == Blend::Hue || type == Blend::Color)  // a + t (rgb(h', s', v_a) - a)
                return corners(t, a, v, lerp);
            // rgb = v' (1 - s' g), g in [0, 1]: s' (saturation) or v' (value) mixed by t.
            const Interval part = type == Blend::Value ? v : unit;
            const Interval mixed = corners(t, part, part, lerp);
            const Interval sat = type == Blend::Value ? unit : mixed;
            const Interval val = type == Blend::Value ? mixed : v;
            return corners(val, sat, unit,
                           [](double v, double s, double g) { return v * (1.0 - s * g); })
                .join(a);
        }
    }
    return kAll;
}

class MixSource final : public CompositeSource {
  public:
    Blend m_type = Blend::Mix;
    bool m_clamp_factor = true, m_clamp = false;
    bool m_per_channel = false;  // fac_color: t per channel (blend mix)
    CompositeInput m_fac, m_a, m_b;

    Rgb value(const TexturePoint& p) const override {
        if (m_per_channel) {
            Rgb t = m_fac.eval(p);
            if (m_clamp_factor) t = glm::clamp(t, Rgb(0.f), Rgb(1.f));
            const Rgb a = m_a.eval(p);
            Rgb r = a + t * (m_b.eval(p) - a);
            if (m_clamp) r = glm::clamp(r, Rgb(0.f), Rgb(1.f));
            return r;
        }
        float t = m_fac.number(p);
        if (m_clamp_factor) t = std::clamp(t, 0.f, 1.f);
        Rgb r = mix(m_type, t, m_a.eval(p), m_b.eval(p));
        if (m_clamp) r = glm::clamp(r, Rgb(0.f), Rgb(1.f));
        return r;
    }
};

Texture build_mix_rgb(TextureBuild& b) {
    check_texture_params(b, kMixRgbTexture);
    auto s = std::make_shared<MixSource>();
    const CompositeParams p(b, kMixRgbTexture);
    s->m_type = Blend(p.choice("blend_type"));
    s->m_clamp_factor = p.flag("clamp_factor");
    s->m_clamp = p.flag("use_clamp");
    const TextureDesc& d = b.desc;
    s->m_per_channel = d.params.values().count("fac_color") ||
                       std::any_of(d.inputs.begin(), d.inputs.end(),
                                   [](const TextureInputDesc& x) { return x.name == "fac_color"; });
    if (s->m_per_channel) {
        const bool fac_given =
            d.params.values().count("fac") ||
            std::any_of(d.inputs.begin(), d.inputs.end(),
                        [](const TextureInputDesc& x) { return x.name == "fac"; });
        if (fac_given) b.fail(p.pointer("fac_color"), "give either fac or fac_color, not both");
        if (s->m_type != Blend::Mix)
            b.fail(p.pointer("fac_color"),
                   "a factor per channel needs blend_type 'mix' (the Mix node's Vector mode)");
    }
    s->m_fac = s->m_per_channel ? p.input("fac_color", true) : p.input("fac", false);
    // A number texture mixes numbers (grey colours stay grey in every blend), unless it
    // reads a channel of the colour.
    const bool colours = b.color || !b.desc.channel.empty();
    s->m_a = p.input("color1", colours);
    s->m_b = p.input("color2", colours);
    Interval all_a = s->m_a.range(0), all_b = s->m_b.range(0);
    for (int c = 1; c < 3; ++c) {
        all_a = all_a.join(s->m_a.range(c));
        all_b = all_b.join(s->m_b.range(c));
    }
    Rgb lo, hi;
    for (int c = 0; c < 3; ++c) {
        Interval t = s->m_fac.range(s->m_per_channel ? c : 0);
        if (s->m_clamp_factor) t = t.clamped(0.0, 1.0);
        Interval r = mix_range(s->m_type, t, s->m_a.range(c), s->m_b.range(c), all_a, all_b);
        if (s->m_clamp) r = r.clamped(0.0, 1.0);
        lo[c] = float(r.lo);
        hi[c] = float(r.hi);
    }
    return make_composite(b, kMixRgbTexture, s, lo, hi, p.reads(),
                          "blend type '" + kBlends[std::size_t(s->m_type)] + "'");
}

}  // namespace

const TextureKindDef kMixRgbTexture{
    "mix_rgb",
    "Blender's Mix RGB node (and the Mix node's Color mode) per hit: `blend_type` of color1 "
    "and color2 by fac (colours, numbers or textures), as Cycles 3.4 (composite: no "
    "coordinates)",
    {
        {"blend_type", ParamType::String, 0, "mix", 0, 0, false, kBlends,
         "Blender's blend type, lower case (LINEAR_LIGHT: linear_light)"},
        {"use_clamp", ParamType::Bool, 0, {}, 0, 0, false, {}, "clamp the result to [0, 1]"},
        {"clamp_factor",
         ParamType::Bool,
         1,
         {},
         0,
         0,
         false,
         {},
         "clamp fac to [0, 1] first (Mix RGB always does; the Mix node's Clamp Factor)"},
        {"fac",
         ParamType::Number,
         0.5,
         {},
         -1e30,
         1e30,
         false,
         {},
         "the factor",
         TextureParamForm::Input},
        {"fac_color",
         ParamType::Color,
         0,
         {},
         0,
         0,
         false,
         {},
         "instead of fac, one factor per channel (blend_type mix only: the Mix node's Vector "
         "mode with a Non-Uniform factor)",
         TextureParamForm::Input,
         Rgb(0.5f)},
        {"color1",
         ParamType::Color,
         0,
         {},
         0,
         0,
         false,
         {},
         "the first colour (default grey 0.5)",
         TextureParamForm::Input,
         Rgb(0.5f)},
        {"color2",
         ParamType::Color,
         0,
         {},
         0,
         0,
         false,
         {},
         "the second colour (default grey 0.5)",
         TextureParamForm::Input,
         Rgb(0.5f)},
    },
    true,
    build_mix_rgb,
    true,
};

}  // namespace facet::render
