// Texture kind "math": Blender 3.4's Math node evaluated per hit (Cycles' svm_math, in float):
// `operation` of the inputs a, b, c (constants or number textures), the result clamped to
// [0, 1] when `use_clamp`. Cycles' safe forms: divide by 0 -> 0; power of a negative base to a
// non-integer exponent -> 0; logarithm of a <= 0 or base <= 0 -> 0 (and log a / log b with
// log b = 0 -> 0); sqrt of max(a, 0); inverse sqrt of a <= 0 -> 0; modulo by 0 -> 0 (fmod
// otherwise); wrap(a, max b, min c) = a - (b - c) floor((a - c) / (b - c)) (c when b = c);
// snap floor(a / b) b (b = 0 -> 0); ping-pong |fract((a - b) / 2b) 2b - b| (b = 0 -> 0);
// smooth min min(a, b) - h^3 c / 6 with h = max(c - |a - b|, 0) / c (c = 0: min), smooth max
// its mirror; compare |a - b| <= max(c, FLT_EPSILON) (or a = b); sign 0 at 0; round
// floor(a + 1/2); arcsine / arccosine of a clamped to [-1, 1].
#include <cfloat>
#include <cmath>
#include <numbers>

#include "composite.h"

namespace facet::render {

namespace {

enum class Op {
    Add,
    Subtract,
    Multiply,
    Divide,
    MultiplyAdd,
    Power,
    Logarithm,
    Sqrt,
    InverseSqrt,
    Absolute,
    Exponent,
    Minimum,
    Maximum,
    LessThan,
    GreaterThan,
    Sign,
    Compare,
    SmoothMin,
    SmoothMax,
    Round,
    Floor,
    Ceil,
    Trunc,
    Fract,
    Modulo,
    Wrap,
    Snap,
    PingPong,
    Sine,
    Cosine,
    Tangent,
    Sinh,
    Cosh,
    Tanh,
    Arcsine,
    Arccosine,
    Arctangent,
    Arctan2,
    Radians,
    Degrees,
};

const std::vector<std::string> kOperations = {
    "add",        "subtract",  "multiply",     "divide",   "multiply_add", "power",
    "logarithm",  "sqrt",      "inverse_sqrt", "absolute", "exponent",     "minimum",
    "maximum",    "less_than", "greater_than", "sign",     "compare",      "smooth_min",
    "smooth_max", "round",     "floor",        "ceil",     "trunc",        "fract",
    "modulo",     "wrap",      "snap",         "pingpong", "sine",         "cosine",
    "tangent",    "sinh",      "cosh",         "tanh",     "arcsine",      "arccosine",
    "arctangent", "arctan2",   "radians",      "degrees",
};

constexpr float kPi = std::numbers::pi_v<float>;

float safe_divide(float a, float b) {
    return b != 0.f ? a / b : 0.f;
}
float fract(float x) {
    return x - std::floor(x);
}
float smooth_min(float a, float b, float k) {
    if (k != 0.f) {
        const float h = std::fmax(k - std::fabs(a - b), 0.f) / k;
        return std::fmin(a, b) - h * h * h * k * (1.f / 6.f);
    }
    return std::fmin(a, b);
}

// Cycles' svm_math.
float math(Op op, float a, float b, float c) {
    switch (op) {
        case Op::Add:
            return a + b;
        case Op::Subtract:
            return a - b;
        case Op::Multiply:
            return a * b;
        case Op::Divide:
            return safe_divide(a, b);
        case Op::MultiplyAdd:
            return a * b + c;
        case Op::Power:
            if (a < 0.f && b != float(int(b))) return 0.f;
            return std::pow(a, b);
        case Op::Logarithm:
            if (a <= 0.f || b <= 0.f) return 0.f;
            return safe_divide(std::log(a), std::log(b));
        case Op::Sqrt:
            return std::sqrt(std::fmax(a, 0.f));
        case Op::InverseSqrt:
            return a > 0.f ? 1.f / std::sqrt(a) : 0.f;
        case Op::Absolute:
            return std::fabs(a);
        case Op::Exponent:
            return std::exp(a);
        case Op::Minimum:
            return std::fmin(a, b);
        case Op::Maximum:
            return std::fmax(a, b);
        case Op::LessThan:
            return a < b ? 1.f : 0.f;
        case Op::GreaterThan:
            return a > b ? 1.f : 0.f;
        case Op::Sign:
            return a == 0.f ? 0.f : a < 0.f ? -1.f : 1.f;
        case Op::Compare:
            return (a == b || std::fabs(a - b) <= std::fmax(c, FLT_EPSILON)) ? 1.f : 0.f;
        case Op::SmoothMin:
            return smooth_min(a, b, c);
        case Op::SmoothMax:
            return -smooth_min(-a, -b, c);
        case Op::Round:
            return std::floor(a + 0.5f);
        case Op::Floor:
            return std::floor(a);
        case Op::Ceil:
            return std::ceil(a);
        case Op::Trunc:
            return a >= 0.f ? std::floor(a) : std::ceil(a);
        case Op::Fract:
            return fract(a);
        case Op::Modulo:
            return b != 0.f ? std::fmod(a, b) : 0.f;
        case Op::Wrap: {
            const float range = b - c;
            return range != 0.f ? a - range * std::floor((a - c) / range) : c;
        }
        case Op::Snap:
            return std::floor(safe_divide(a, b)) * b;
        case Op::PingPong:
            return b != 0.f ? std::fabs(fract((a - b) / (b * 2.f)) * b * 2.f - b) : 0.f;
        case Op::Sine:
            return std::sin(a);
        case Op::Cosine:
            return std::cos(a);
        case Op::Tangent:
            return std::tan(a);
        case Op::Sinh:
            return std::sinh(a);
        case Op::Cosh:
            return std::cosh(a);
        case Op::Tanh:
            return std::tanh(a);
        case Op::Arcsine:
            return std::asin(std::clamp(a, -1.f, 1.f));
        case Op::Arccosine:
            return std::acos(std::clamp(a, -1.f, 1.f));
        case Op::Arctangent:
            return std::atan(a);
        case Op::Arctan2:
            return std::atan2(a, b);
        case Op::Radians:
            return a * (kPi / 180.f);
        case Op::Degrees:
            return a * (180.f / kPi);
    }
    return 0.f;
}

constexpr Interval kAll{-INFINITY, INFINITY};

// The range of x -> sin(x + shift) over [lo, hi] (cosine: shift pi/2).
Interval sine_range(Interval a, double shift) {
    const double lo = a.lo + shift, hi = a.hi + shift;
    if (!(hi - lo < 2.0 * std::numbers::pi)) return {-1.0, 1.0};
    Interval r = Interval::hull({std::sin(lo), std::sin(hi)});
    // A maximum at pi/2 + 2 pi k, a minimum at -pi/2 + 2 pi k inside [lo, hi].
    const double two_pi = 2.0 * std::numbers::pi;
    if (std::ceil((lo - std::numbers::pi / 2) / two_pi) <=
        std::floor((hi - std::numbers::pi / 2) / two_pi))
        r.hi = 1.0;
    if (std::ceil((lo + std::numbers::pi / 2) / two_pi) <=
        std::floor((hi + std::numbers::pi / 2) / two_pi))
        r.lo = -1.0;
    return r;
}

// x^y over a box with x >= 0: monotonic in each variable, extremes at the corners; 0^y with
// y < 0 is unbounded.
Interval pow_box(Interval x, Interval y) {
    if (x.lo <= 0.0 && y.lo < 0.0) return {0.0, INFINITY};
    return Interval::hull(
        {std::pow(x.lo, y.lo), std::pow(x.lo, y.hi), std::pow(x.hi, y.lo), std::pow(x.hi, y.hi)});
}

Interval divide(Interval a, Interval b) {
    if (b.lo == 0.0 && b.hi == 0.0) return Interval::of(0.0);
    if (b.contains(0.0)) return a.lo == 0.0 && a.hi == 0.0 ? Interval::of(0.0) : kAll;
    return a * Interval{1.0 / b.hi, 1.0 / b.lo};
}

Interval smooth_min_range(Interval a, Interval b, Interval c) {
    const Interval m{std::min(a.lo, b.lo), std::min(a.hi, b.hi)};
    // h in [0, 1] for c > 0 (0 otherwise): min(a, b) - h^3 c / 6 >= min(a, b) - c / 6.
    return {m.lo - std::max(c.hi, 0.0) / 6.0, m.hi};
}

// A conservative range of math(op, a, b, c) over the inputs' ranges (composite.h).
Interval math_range(Op op, Interval a, Interval b, Interval c) {
    const double max_abs_a = std::max(std::fabs(a.lo), std::fabs(a.hi));
    const double max_abs_b = std::max(std::fabs(b.lo), std::fabs(b.hi));
    switch (op) {
        case Op::Add:
            return a + b;
        case Op::Subtract:
            return a - b;
        case Op::Multiply:
            return a * b;
        case Op::Divide:
            return divide(a, b);
        case Op::MultiplyAdd:
            return a * b + c;
        case Op::Power: {
            if (a.lo >= 0.0) return pow_box(a, b);
            // A negative base: |a|^b (integer b) with either sign, or 0.
            const double lo_abs =
                a.contains(0.0) ? 0.0 : std::min(std::fabs(a.lo), std::fabs(a.hi));
            const double m = pow_box({lo_abs, max_abs_a}, b).hi;
            return Interval{-m, m}.join(Interval::of(0.0));
        }
        case Op::Logarithm: {
            if (a.hi <= 0.0 || b.hi <= 0.0) return Interval::of(0.0);
            const Interval la{a.lo > 0.0 ? std::log(a.lo) : -INFINITY, std::log(a.hi)};
            const Interval lb{b.lo > 0.0 ? std::log(b.lo) : -INFINITY, std::log(b.hi)};
            return divide(la, lb).join(Interval::of(0.0));
        }
        case Op::Sqrt:
            return {std::sqrt(std::max(a.lo, 0.0)), std::sqrt(std::max(a.hi, 0.0))};
        case Op::InverseSqrt:
            if (a.hi <= 0.0) return Interval::of(0.0);
            if (a.lo > 0.0) return {1.0 / std::sqrt(a.hi), 1.0 / std::sqrt(a.lo)};
            return {0.0, INFINITY};
        case Op::Absolute:
            return {a.contains(0.0) ? 0.0 : std::min(std::fabs(a.lo), std::fabs(a.hi)), max_abs_a};
        case Op::Exponent:
            return {std::exp(a.lo), std::exp(a.hi)};
        case Op::Minimum:
            return {std::min(a.lo, b.lo), std::min(a.hi, b.hi)};
        case Op::Maximum:
            return {std::max(a.lo, b.lo), std::max(a.hi, b.hi)};
        case Op::LessThan:
        case Op::GreaterThan:
        case Op::Compare:
            return {0.0, 1.0};
        case Op::Sign:
            return {a.lo < 0.0   ? -1.0
                    : a.lo > 0.0 ? 1.0
                                 : 0.0,
                    a.hi > 0.0   ? 1.0
                    : a.hi < 0.0 ? -1.0
                                 : 0.0};
        case Op::SmoothMin:
            return smooth_min_range(a, b, c);
        case Op::SmoothMax:
            return -smooth_min_range(-a, -b, c);
        case Op::Round:
            return {std::floor(a.lo + 0.5), std::floor(a.hi + 0.5)};
        case Op::Floor:
            return {std::floor(a.lo), std::floor(a.hi)};
        case Op::Ceil:
            return {std::ceil(a.lo), std::ceil(a.hi)};
        case Op::Trunc:
            return {std::trunc(a.lo), std::trunc(a.hi)};
        case Op::Fract:
            return {0.0, 1.0};
        case Op::Modulo:  // |fmod(a, b)| < |b|, |fmod(a, b)| <= |a|, the sign of a; or 0
            return {a.lo < 0.0 ? std::max(a.lo, -max_abs_b) : 0.0,
                    a.hi > 0.0 ? std::min(a.hi, max_abs_b) : 0.0};
        case Op::Wrap:
            return {std::min(b.lo, c.lo), std::max(b.hi, c.hi)};
        case Op::Snap: {  // |floor(a / b) b| <= |a| + |b|
            const double m = max_abs_a + max_abs_b;
            return {-m, m};
        }
        case Op::PingPong:
            return {0.0, max_abs_b};
        case Op::Sine:
            return sine_range(a, 0.0);
        case Op::Cosine:
            return sine_range(a, std::numbers::pi / 2);
        case Op::Tangent: {
            // Monotonic between the poles pi/2 + k pi.
            const double k0 = std::ceil((a.lo - std::numbers::pi / 2) / std::numbers::pi);
            const double k1 = std::floor((a.hi - std::numbers::pi / 2) / std::numbers::pi);
            if (!(k0 > k1)) return kAll;
            return {std::tan(a.lo), std::tan(a.hi)};
        }
        case Op::Sinh:
            return {std::sinh(a.lo), std::sinh(a.hi)};
        case Op::Cosh: {
            const double m = a.contains(0.0) ? 0.0 : std::min(std::fabs(a.lo), std::fabs(a.hi));
            return {std::cosh(m), std::cosh(max_abs_a)};
        }
        case Op::Tanh:
            return {std::tanh(a.lo), std::tanh(a.hi)};
        case Op::Arcsine:
            return {std::asin(std::clamp(a.lo, -1.0, 1.0)), std::asin(std::clamp(a.hi, -1.0, 1.0))};
        case Op::Arccosine:
            return {std::acos(std::clamp(a.hi, -1.0, 1.0)), std::acos(std::clamp(a.lo, -1.0, 1.0))};
        case Op::Arctangent:
            return {std::atan(a.lo), std::atan(a.hi)};
        case Op::Arctan2:
            return {-std::numbers::pi, std::numbers::pi};
        case Op::Radians:
            return a * Interval::of(std::numbers::pi / 180.0);
        case Op::Degrees:
            return a * Interval::of(180.0 / std::numbers::pi);
    }
    return kAll;
}

class MathSource final : public CompositeSource {
  public:
    Op m_op = Op::Add;
    bool m_clamp = false;
    CompositeInput m_a, m_b, m_c;

    Rgb value(const TexturePoint& p) const override {
        float r = math(m_op, m_a.number(p), m_b.number(p), m_c.number(p));
        if (m_clamp) r = std::clamp(r, 0.f, 1.f);  // (NaN stays NaN, as in Cycles' saturatef)
        return Rgb(r);
    }
};

Texture build_math(TextureBuild& b) {
    check_texture_params(b, kMathTexture);
    auto s = std::make_shared<MathSource>();
    const CompositeParams p(b, kMathTexture);
    s->m_op = Op(p.choice("operation"));
    s->m_clamp = p.flag("use_clamp");
    s->m_a = p.input("a", false);
    s->m_b = p.input("b", false);
    s->m_c = p.input("c", false);
    // (Float evaluation may round an ulp past these double bounds; users of the range clamp
    // to it.)
    Interval r = math_range(s->m_op, s->m_a.range(), s->m_b.range(), s->m_c.range());
    if (s->m_clamp) r = r.clamped(0.0, 1.0);
    return make_composite(b, kMathTexture, s, Rgb(float(r.lo)), Rgb(float(r.hi)), p.reads(),
                          "operation '" + kOperations[std::size_t(s->m_op)] + "'");
}

}  // namespace

int math_operation(std::string_view name) {
    const auto it = std::find(kOperations.begin(), kOperations.end(), name);
    return it == kOperations.end() ? -1 : int(it - kOperations.begin());
}

float math_operation_value(int op, float a, float b, float c) {
    return math(Op(op), a, b, c);
}

Interval math_operation_range(int op, Interval a, Interval b, Interval c) {
    return math_range(Op(op), a, b, c);
}

const TextureKindDef kMathTexture{
    "math",
    "Blender's Math node per hit: `operation` of the inputs a, b, c (numbers or number "
    "textures), Cycles 3.4's safe forms (composite: no coordinates)",
    {
        {"operation", ParamType::String, 0, "add", 0, 0, false, kOperations,
         "Blender's operation, lower case (MULTIPLY_ADD: multiply_add)"},
        {"use_clamp", ParamType::Bool, 0, {}, 0, 0, false, {}, "clamp the result to [0, 1]"},
        {"a",
         ParamType::Number,
         0.5,
         {},
         -1e30,
         1e30,
         false,
         {},
         "the first Value",
         TextureParamForm::Input},
        {"b",
         ParamType::Number,
         0.5,
         {},
         -1e30,
         1e30,
         false,
         {},
         "the second Value",
         TextureParamForm::Input},
        {"c",
         ParamType::Number,
         0.5,
         {},
         -1e30,
         1e30,
         false,
         {},
         "the third Value",
         TextureParamForm::Input},
    },
    true,
    build_math,
    true,
};

}  // namespace facet::render
