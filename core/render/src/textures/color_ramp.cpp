// Texture kind "color_ramp": Blender 3.4's ColorRamp node evaluated per hit, as Cycles 3.4
// does it: the ramp (its stops and `interpolation`, Blender's BKE_colorband_evaluate in RGB
// mode, in float) is tabulated at 256 points i / 255, and the value at fac is read from the
// table at clamp(fac, 0, 1) * 255, linearly between entries (Cycles' rgb_ramp_lookup; Constant
// interpolation reads the entry below, no blend).
//
// The ramp at x, stops (p_i, c_i) in order of position (Blender's colorband):
// - one stop: c_0 everywhere;
// - constant, linear, ease: c_0 for x <= p_0, the last stop's colour after the last stop;
//   between stops p_{k-1} <= x < p_k: constant c_{k-1}; linear c_{k-1} + f (c_k - c_{k-1})
//   with f = (x - p_{k-1}) / (p_k - p_{k-1}) (f = 0 for coincident stops; 1 past the last);
//   ease with f replaced by 3 f^2 - 2 f^3;
// - cardinal and b_spline: the four stops around x (the end stops repeated past the ends, the
//   span before the first stop running from position 0 and after the last to position 1)
//   weighted by Blender's key_curve_position_weights (cardinal tension 0.71, uniform cubic
//   B-spline), f clamped to [0, 1], the result clamped to [0, 1].
// Outputs: `color` (RGB) or `alpha` (A).
#include <array>
#include <vector>

#include "composite.h"

namespace facet::render {

namespace {

enum class Interp { Constant, Linear, Ease, Cardinal, BSpline };

const std::vector<std::string> kInterpolations = {"constant", "linear", "ease", "cardinal",
                                                  "b_spline"};

constexpr int kTableSize = 256;  // Cycles' RAMP_TABLE_SIZE

using Rgba = glm::vec4;

// Blender's key_curve_position_weights for the cardinal (0.71) and B-spline curves.
void curve_weights(float t, float w[4], bool cardinal) {
    const float t2 = t * t, t3 = t2 * t;
    if (cardinal) {
        const float fc = 0.71f;
        w[0] = -fc * t3 + 2.f * fc * t2 - fc * t;
        w[1] = (2.f - fc) * t3 + (fc - 3.f) * t2 + 1.f;
        w[2] = (fc - 2.f) * t3 + (3.f - 2.f * fc) * t2 + fc * t;
        w[3] = fc * t3 - fc * t2;
    } else {
        w[0] = -0.16666666f * t3 + 0.5f * t2 - 0.5f * t + 0.16666666f;
        w[1] = 0.5f * t3 - t2 + 0.66666666f;
        w[2] = -0.5f * t3 + 0.5f * t2 + 0.5f * t + 0.16666666f;
        w[3] = 0.16666666f * t3;
    }
}

struct Stop {
    float pos;
    Rgba c;
};

// The ramp at x (Blender's colorband evaluation in RGB mode; see the top of the file).
Rgba ramp(const std::vector<Stop>& s, Interp ip, float x) {
    const int n = int(s.size());
    const bool spline = ip == Interp::Cardinal || ip == Interp::BSpline;
    if (n == 1) return s[0].c;
    if (x <= s[0].pos && !spline) return s[0].c;
    int a = 0;  // the first stop past x
    while (a < n && !(s[std::size_t(a)].pos > x)) ++a;
    // right (cbd1) and left (cbd2) ends of the span holding x.
    Stop right, left;
    if (a == n) {
        left = s[std::size_t(n - 1)];
        right = left;
        right.pos = 1.f;
    } else if (a == 0) {
        right = s[0];
        left = right;
        left.pos = 0.f;
    } else {
        right = s[std::size_t(a)];
        left = s[std::size_t(a - 1)];
    }
    if (a == n && !spline) return left.c;
    if (ip == Interp::Constant) return left.c;
    float f =
        left.pos != right.pos ? (x - right.pos) / (left.pos - right.pos) : (a != n ? 0.f : 1.f);
    if (spline) {
        // The stops beyond: after the right end (cbd0) and before the left one (cbd3).
        const Stop& beyond_right = a >= n - 1 ? right : s[std::size_t(a + 1)];
        const Stop& before_left = a < 2 ? left : s[std::size_t(a - 2)];
        f = std::clamp(f, 0.f, 1.f);
        float w[4];
        curve_weights(f, w, ip == Interp::Cardinal);
        const Rgba c =
            w[3] * before_left.c + w[2] * left.c + w[1] * right.c + w[0] * beyond_right.c;
        return glm::clamp(c, Rgba(0.f), Rgba(1.f));
    }
    if (ip == Interp::Ease) {
        const float f2 = f * f;
        f = 3.f * f2 - 2.f * f2 * f;
    }
    return (1.f - f) * right.c + f * left.c;
}

class ColorRampSource final : public CompositeSource {
  public:
    std::array<Rgba, kTableSize> m_table{};
    bool m_interpolate = true, m_alpha = false;
    CompositeInput m_fac;

    Rgb value(const TexturePoint& p) const override {
        // Cycles' rgb_ramp_lookup without extrapolation.
        float f = std::clamp(m_fac.number(p), 0.f, 1.f) * float(kTableSize - 1);
        const int i = std::clamp(int(f), 0, kTableSize - 1);  // (a NaN fac reads entry 0)
        const float t = f - float(i);
        Rgba c = m_table[std::size_t(i)];
        if (m_interpolate && t > 0.f) c = (1.f - t) * c + t * m_table[std::size_t(i + 1)];
        return m_alpha ? Rgb(c.a) : Rgb(c);
    }
};

Texture build_color_ramp(TextureBuild& b) {
    check_texture_params(b, kColorRampTexture);
    auto s = std::make_shared<ColorRampSource>();
    const CompositeParams p(b, kColorRampTexture);
    const Interp ip = Interp(p.choice("interpolation"));
    s->m_alpha = p.choice("output") == 1;
    s->m_interpolate = ip != Interp::Constant;
    s->m_fac = p.input("fac", false);
    const std::string sp = b.ptr + "/color_ramp/stops";
    if (b.desc.stops.empty()) b.fail(sp, "a colour ramp needs at least one stop");
    std::vector<Stop> stops;
    for (const TextureStop& t : b.desc.stops) stops.push_back({float(t.position), Rgba(t.color)});
    Rgba lo(INFINITY), hi(-INFINITY);
    for (int i = 0; i < kTableSize; ++i) {
        const Rgba c = ramp(stops, ip, float(i) / float(kTableSize - 1));
        s->m_table[std::size_t(i)] = c;
        lo = glm::min(lo, c);
        hi = glm::max(hi, c);
    }
    const bool grey_needed = !b.color && !s->m_alpha && b.desc.channel.empty();
    if (grey_needed && (lo.r != lo.g || lo.r != lo.b || hi.r != hi.g || hi.r != hi.b))
        b.fail(p.pointer("output"),
               "a number parameter needs a grey ramp or the alpha output (this ramp has colours)");
    if (grey_needed) {
        for (std::size_t i = 0; i < b.desc.stops.size(); ++i) {
            const glm::dvec4& c = b.desc.stops[i].color;
            if (c.r != c.g || c.r != c.b)
                b.fail(sp + "/" + std::to_string(i) + "/color",
                       "a number parameter needs grey stops (or the alpha output)");
        }
    }
    const Rgb l = s->m_alpha ? Rgb(lo.a) : Rgb(lo), h = s->m_alpha ? Rgb(hi.a) : Rgb(hi);
    return make_composite(b, kColorRampTexture, s, l, h, p.reads(), "colour ramp");
}

}  // namespace

const TextureKindDef kColorRampTexture{
    "color_ramp",
    "Blender's ColorRamp node per hit (RGB mode): the `stops` interpolated at fac (a number or "
    "a number texture), tabulated at 256 points as Cycles 3.4 does (composite: no coordinates)",
    {
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
        {"interpolation", ParamType::String, 0, "linear", 0, 0, false, kInterpolations,
         "Blender's interpolation, lower case"},
        {"stops",
         ParamType::String,
         0,
         {},
         0,
         0,
         false,
         {},
         "the stops in order of position: [{\"position\": p in [0, 1], \"color\": [r, g, b] or "
         "[r, g, b, a] (linear; alpha 1 by default)}, ...], at least one",
         TextureParamForm::Stops},
        {"output", ParamType::String, 0, "color", 0, 0, false, {"color", "alpha"}, kOutputDoc},
    },
    true,
    build_color_ramp,
    true,
};

}  // namespace facet::render
