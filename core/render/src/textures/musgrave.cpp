// Texture kind "musgrave": Blender 3.4's Musgrave Texture node (Cycles' svm_musgrave; Musgrave,
// "Texturing and Modeling: A Procedural Approach", ch. 16) of signed Perlin noise s
// (cycles_noise.h) in 1-4 dimensions, at the point (procedural.h) times Scale (W x Scale the
// 4th or only coordinate). With octaves o = clamp(Detail, 0, 15), lacunarity L =
// max(Lacunarity, 1e-5), H = max(Dimension, 1e-5), w_i = L^(-H i) and p_i = L^i p:
//  - fbm: sum over the integer octaves of w_i s(p_i), plus frac(o) times the next term;
//  - multifractal: the product of (w_i s(p_i) + 1), the fraction scaling the last term's w;
//  - hetero_terrain: v = Offset + s(p_0), then v += (s(p_i) + Offset) w_i v;
//  - hybrid_multifractal: v = s(p_0) + Offset, weight = Gain v; then, while weight > 0.001,
//    weight = min(weight, 1), signal = (s(p_i) + Offset) w_i, v += weight signal,
//    weight *= Gain signal;
//  - ridged_multifractal: signal = (Offset - |s(p_0)|)^2, v = signal; then weight =
//    clamp(signal Gain, 0, 1), signal = (Offset - |s(p_i)|)^2 weight, v += signal w_i.
// The value is grey (Fac) and unclamped: it may be negative or above 1.
#include "cycles_noise.h"
#include "procedural.h"

#include <algorithm>
#include <cmath>

namespace facet::render {

namespace {

using cycles::vec2;
using cycles::vec3;
using cycles::vec4;

enum class MusgraveType { Fbm, Multifractal, HeteroTerrain, HybridMultifractal, Ridged };

class MusgraveSource final : public ProceduralSource {
  public:
    int m_dimensions = 3;
    MusgraveType m_type = MusgraveType::Fbm;
    float m_scale_in = 5.f, m_detail = 2.f, m_dimension = 2.f, m_lacunarity = 2.f, m_offset = 0.f,
          m_gain = 1.f, m_w = 0.f;

    template <class P>
    float musgrave(P p) const {
        using cycles::snoise;
        const float octaves = m_detail, lac = m_lacunarity;
        const float pwHL = std::pow(lac, -m_dimension);
        const int n = int(octaves);
        const float rmd = octaves - std::floor(octaves);
        switch (m_type) {
            case MusgraveType::Fbm: {
                float value = 0.f, pwr = 1.f;
                for (int i = 0; i < n; ++i) {
                    value += snoise(p) * pwr;
                    pwr *= pwHL;
                    p *= lac;
                }
                if (rmd != 0.f) value += rmd * snoise(p) * pwr;
                return value;
            }
            case MusgraveType::Multifractal: {
                float value = 1.f, pwr = 1.f;
                for (int i = 0; i < n; ++i) {
                    value *= (pwr * snoise(p) + 1.f);
                    pwr *= pwHL;
                    p *= lac;
                }
                if (rmd != 0.f) value *= (rmd * pwr * snoise(p) + 1.f);
                return value;
            }
            case MusgraveType::HeteroTerrain: {
                float pwr = pwHL;
                float value = m_offset + snoise(p);
                p *= lac;
                for (int i = 1; i < n; ++i) {
                    const float increment = (snoise(p) + m_offset) * pwr * value;
                    value += increment;
                    pwr *= pwHL;
                    p *= lac;
                }
                if (rmd != 0.f) {
                    const float increment = (snoise(p) + m_offset) * pwr * value;
                    value += rmd * increment;
                }
                return value;
            }
            case MusgraveType::HybridMultifractal: {
                float pwr = pwHL;
                float result = snoise(p) + m_offset;
                float weight = m_gain * result;
                p *= lac;
                for (int i = 1; weight > 0.001f && i < n; ++i) {
                    if (weight > 1.f) weight = 1.f;
                    const float signal = (snoise(p) + m_offset) * pwr;
                    pwr *= pwHL;
                    result += weight * signal;
                    weight *= m_gain * signal;
                    p *= lac;
                }
                if (rmd != 0.f && weight > 0.001f) {
                    if (weight > 1.f) weight = 1.f;
                    const float signal = (snoise(p) + m_offset) * pwr;
                    result += rmd * weight * signal;
                }
                return result;
            }
            case MusgraveType::Ridged:
            default: {
                float pwr = pwHL;
                float signal = m_offset - std::fabs(snoise(p));
                signal *= signal;
                float result = signal, weight = 1.f;
                for (int i = 1; i < n; ++i) {
                    p *= lac;
                    weight = std::clamp(signal * m_gain, 0.f, 1.f);
                    signal = m_offset - std::fabs(snoise(p));
                    signal *= signal;
                    signal *= weight;
                    result += signal * pwr;
                    pwr *= pwHL;
                }
                return result;
            }
        }
    }

    Rgb pattern(const Vec3& x) const override {
        const Vec3 v = x * m_scale_in;
        const float w = m_w * m_scale_in;
        switch (m_dimensions) {
            case 1:
                return Rgb(musgrave(w));
            case 2:
                return Rgb(musgrave(vec2(v.x, v.y)));
            case 4:
                return Rgb(musgrave(vec4(v.x, v.y, v.z, w)));
            default:
                return Rgb(musgrave(vec3(v)));
        }
    }
};

// Bounds of the value, from |s| <= kS (Perlin noise's scaled extremes stay within a few
// percent of 1) and each type's recurrence taken at its extremes.
void musgrave_range(const MusgraveSource& s, float& lo, float& hi) {
    constexpr double kS = 1.1;
    const double pwHL = std::pow(double(s.m_lacunarity), -double(s.m_dimension));
    const int terms = int(std::ceil(double(s.m_detail))) + 1;
    const double off = std::fabs(double(s.m_offset)), gain = std::fabs(double(s.m_gain));
    double a = 0.0, v = 1.0, h = off + kS, pwr = 1.0;
    for (int i = 0; i < terms; ++i) {
        a += kS * pwr;
        v *= 1.0 + kS * pwr;
        if (i > 0) h += (kS + off) * pwr * h;
        pwr *= pwHL;
    }
    double bound = 0.0;
    switch (s.m_type) {
        case MusgraveType::Fbm:
            bound = a;
            break;
        case MusgraveType::Multifractal:
            bound = v;
            break;
        case MusgraveType::HeteroTerrain:
            bound = h;
            break;
        case MusgraveType::HybridMultifractal:
            bound = (off + kS) * (1.0 + std::max(1.0, gain) * a);
            break;
        case MusgraveType::Ridged:
            bound = (off + kS) * (off + kS) * (1.0 + a);
            break;
    }
    hi = float(std::min(bound, 1e30));
    lo = s.m_type == MusgraveType::Ridged ? 0.f : -hi;
}

Texture build_musgrave(TextureBuild& b) {
    auto s = std::make_shared<MusgraveSource>();
    const ProceduralParams p(b, kMusgraveTexture);
    make_procedural(b, kMusgraveTexture, s, Rgb(0.f), Rgb(0.f));  // validates the parameters
    s->m_dimensions = int(p.number("dimensions"));
    s->m_type = MusgraveType(p.choice("type"));
    s->m_scale_in = float(p.number("scale"));
    s->m_detail = std::clamp(float(p.number("detail")), 0.f, 15.f);
    s->m_dimension = std::max(float(p.number("dimension")), 1e-5f);
    s->m_lacunarity = std::max(float(p.number("lacunarity")), 1e-5f);
    s->m_offset = float(p.number("offset"));
    s->m_gain = float(p.number("gain"));
    s->m_w = float(p.number("w"));
    float lo = 0.f, hi = 0.f;
    musgrave_range(*s, lo, hi);
    if (b.radiance && lo < 0.f)
        b.fail(p.pointer("type"),
               "a Musgrave value can be negative, which an emission cannot be (map it to a "
               "non-negative range first)");
    return make_procedural(b, kMusgraveTexture, s, Rgb(lo), Rgb(hi));
}

}  // namespace

const TextureKindDef kMusgraveTexture{
    "musgrave",
    "Blender's Musgrave Texture: fractals of signed Perlin noise (Cycles 3.4), unclamped",
    {
        {"dimensions", ParamType::Number, 3, {}, 1, 4, true, {}, "1, 2, 3 or 4 (W the 4th)"},
        {"type",
         ParamType::String,
         0,
         "fbm",
         0,
         0,
         false,
         {"fbm", "multifractal", "hetero_terrain", "hybrid_multifractal", "ridged_multifractal"},
         "the fractal"},
        {"scale", ParamType::Number, 5, {}, -1e30, 1e30, false, {}, "Scale"},
        {"detail", ParamType::Number, 2, {}, 0, 15, false, {}, "Detail (octaves)"},
        {"dimension", ParamType::Number, 2, {}, 0, 1e30, false, {}, "Dimension (H)"},
        {"lacunarity", ParamType::Number, 2, {}, 0, 1e30, false, {}, "Lacunarity"},
        {"offset", ParamType::Number, 0, {}, -1e30, 1e30, false, {}, "Offset"},
        {"gain", ParamType::Number, 1, {}, -1e30, 1e30, false, {}, "Gain"},
        {"w", ParamType::Number, 0, {}, -1e30, 1e30, false, {}, "W (1D and 4D)"},
    },
    true,
    build_musgrave,
};

}  // namespace facet::render
