// Texture kind "vector_math": Blender 3.4's Vector Math node evaluated per hit (Cycles'
// svm_vector_math, in float): `operation` of the vectors a, b, c (colours, numbers as grey, or
// textures) and the number `scale`. Component-wise operations are the Math node's (math.cpp:
// safe divide, snap, modulo, wrap(a, max b, min c), fraction, ...); cross_product, project
// (dot(a, b) / dot(b, b) b, 0 when b = 0), reflect (a - 2 dot(a, n) n, n = b normalised; a
// when b = 0), refract (eta a - (eta d + sqrt k) n, d = dot(n, a), k = 1 - eta^2 (1 - d^2),
// n = b normalised, eta = scale; 0 when k < 0), faceforward (a when dot(c, b) < 0, else -a),
// scale (a scale), normalize (a / |a|, a when |a| = 0). dot_product, distance and length give
// the Value output (`output` "value", grey); the others the Vector output (`output` "vector").
// Ranges (composite.h): component-wise ones as Math's; cross and dot by interval products;
// project and reflect within |a|; refract within 2 |eta| |a| + sqrt(1 + eta^2 |a|^2); length
// and distance between the box's nearest and farthest points from 0.
#include <cmath>

#include "composite.h"

namespace facet::render {

namespace {

enum class Op {
    Add,
    Subtract,
    Multiply,
    Divide,
    MultiplyAdd,
    CrossProduct,
    Project,
    Reflect,
    Refract,
    Faceforward,
    DotProduct,
    Distance,
    Length,
    Scale,
    Normalize,
    Snap,
    Floor,
    Ceil,
    Modulo,
    Wrap,
    Fraction,
    Absolute,
    Minimum,
    Maximum,
    Sine,
    Cosine,
    Tangent,
};

const std::vector<std::string> kOperations = {
    "add",     "subtract", "multiply",  "divide",      "multiply_add", "cross_product",
    "project", "reflect",  "refract",   "faceforward", "dot_product",  "distance",
    "length",  "scale",    "normalize", "snap",        "floor",        "ceil",
    "modulo",  "wrap",     "fraction",  "absolute",    "minimum",      "maximum",
    "sine",    "cosine",   "tangent",
};

const std::vector<std::string> kOutputs = {"vector", "value"};

bool value_output(Op op) {
    return op == Op::DotProduct || op == Op::Distance || op == Op::Length;
}

// The Math node's operation applied per component (-1: not a component-wise operation).
int component_op(Op op) {
    switch (op) {
        case Op::Add:
            return math_operation("add");
        case Op::Subtract:
            return math_operation("subtract");
        case Op::Multiply:
            return math_operation("multiply");
        case Op::Divide:
            return math_operation("divide");
        case Op::MultiplyAdd:
            return math_operation("multiply_add");
        case Op::Snap:
            return math_operation("snap");
        case Op::Floor:
            return math_operation("floor");
        case Op::Ceil:
            return math_operation("ceil");
        case Op::Modulo:
            return math_operation("modulo");
        case Op::Wrap:
            return math_operation("wrap");
        case Op::Fraction:
            return math_operation("fract");
        case Op::Absolute:
            return math_operation("absolute");
        case Op::Minimum:
            return math_operation("minimum");
        case Op::Maximum:
            return math_operation("maximum");
        case Op::Sine:
            return math_operation("sine");
        case Op::Cosine:
            return math_operation("cosine");
        case Op::Tangent:
            return math_operation("tangent");
        default:
            return -1;
    }
}

// Cycles' float3 helpers, in its evaluation order.
float dot(const Rgb& a, const Rgb& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
float length(const Rgb& a) {
    return std::sqrt(dot(a, a));
}
// safe_normalize: a when |a| = 0.
Rgb normalize(const Rgb& a) {
    const float t = length(a);
    return t != 0.f ? a * (1.f / t) : a;
}
Rgb cross(const Rgb& a, const Rgb& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// The interval of x^2 over x in a.
Interval square(Interval a) {
    const double m = std::max(a.lo * a.lo, a.hi * a.hi);
    return {a.contains(0.0) ? 0.0 : std::min(a.lo * a.lo, a.hi * a.hi), m};
}

// The range of |v| over the box v in a.
Interval length_range(const Interval a[3]) {
    const Interval s = square(a[0]) + square(a[1]) + square(a[2]);
    return {std::sqrt(s.lo), std::sqrt(s.hi)};
}

class VectorMathSource final : public CompositeSource {
  public:
    Op m_op = Op::Add;
    int m_component_op = -1;
    CompositeInput m_a, m_b, m_c, m_s;

    Rgb value(const TexturePoint& p) const override {
        const Rgb a = m_a.eval(p);
        if (m_component_op >= 0) {
            const Rgb b = m_b.eval(p);
            const Rgb c = m_op == Op::MultiplyAdd || m_op == Op::Wrap ? m_c.eval(p) : Rgb(0.f);
            Rgb r;
            for (int k = 0; k < 3; ++k)
                r[k] = math_operation_value(m_component_op, a[k], b[k], c[k]);
            return r;
        }
        switch (m_op) {
            case Op::CrossProduct:
                return cross(a, m_b.eval(p));
            case Op::Project: {
                const Rgb b = m_b.eval(p);
                const float l2 = dot(b, b);
                return l2 != 0.f ? (dot(a, b) / l2) * b : Rgb(0.f);
            }
            case Op::Reflect: {
                const Rgb n = normalize(m_b.eval(p));
                return a - 2.f * n * dot(a, n);
            }
            case Op::Refract: {
                const Rgb n = normalize(m_b.eval(p));
                const float eta = m_s.number(p);
                const float d = dot(n, a);
                const float k = 1.f - eta * eta * (1.f - d * d);
                if (k < 0.f) return Rgb(0.f);
                return eta * a - (eta * d + std::sqrt(k)) * n;
            }
            case Op::Faceforward:
                return dot(m_c.eval(p), m_b.eval(p)) < 0.f ? a : -a;
            case Op::DotProduct:
                return Rgb(dot(a, m_b.eval(p)));
            case Op::Distance:
                return Rgb(length(a - m_b.eval(p)));
            case Op::Length:
                return Rgb(length(a));
            case Op::Scale:
                return a * m_s.number(p);
            case Op::Normalize:
                return normalize(a);
            default:
                return Rgb(0.f);
        }
    }
};

// A conservative range of the value's channels (composite.h).
void vector_math_range(const VectorMathSource& s, Interval out[3]) {
    Interval a[3], b[3], c[3];
    for (int k = 0; k < 3; ++k) a[k] = s.m_a.range(k), b[k] = s.m_b.range(k), c[k] = s.m_c.range(k);
    const Interval sc = s.m_s.range();
    const double len_a = length_range(a).hi;
    auto all = [&](Interval r) {
        for (int k = 0; k < 3; ++k) out[k] = r;
    };
    if (s.m_component_op >= 0) {
        for (int k = 0; k < 3; ++k)
            out[k] = math_operation_range(s.m_component_op, a[k], b[k], c[k]);
        return;
    }
    switch (s.m_op) {
        case Op::CrossProduct:
            for (int k = 0; k < 3; ++k) {
                const int i = (k + 1) % 3, j = (k + 2) % 3;
                out[k] = a[i] * b[j] - a[j] * b[i];
            }
            return;
        case Op::Project:  // |dot(a, b) b / |b|^2| <= |a|
        case Op::Reflect:  // |a - 2 dot(a, n) n| = |a| (a when b = 0)
            return all({-len_a, len_a});
        case Op::Refract: {  // |n| <= 1, |d| <= |a|, 0 <= k <= 1 + eta^2 |a|^2
            const double e = std::max(std::fabs(sc.lo), std::fabs(sc.hi));
            const double m = 2.0 * e * len_a + std::sqrt(1.0 + e * e * len_a * len_a);
            return all({-m, m});
        }
        case Op::Faceforward:
            for (int k = 0; k < 3; ++k) out[k] = a[k].join(-a[k]);
            return;
        case Op::DotProduct:
            return all(a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
        case Op::Distance: {
            const Interval d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
            return all(length_range(d));
        }
        case Op::Length:
            return all(length_range(a));
        case Op::Scale:
            for (int k = 0; k < 3; ++k) out[k] = a[k] * sc;
            return;
        case Op::Normalize:  // each component |x| / |a| <= 1, with the sign of x
            for (int k = 0; k < 3; ++k)
                out[k] = {a[k].lo < 0.0 ? -1.0 : 0.0, a[k].hi > 0.0 ? 1.0 : 0.0};
            return;
        default:
            return all({-INFINITY, INFINITY});
    }
}

Texture build_vector_math(TextureBuild& b) {
    check_texture_params(b, kVectorMathTexture);
    auto s = std::make_shared<VectorMathSource>();
    const CompositeParams p(b, kVectorMathTexture);
    s->m_op = Op(p.choice("operation"));
    s->m_component_op = component_op(s->m_op);
    const bool value = p.choice("output") == 1;
    const std::string& name = kOperations[std::size_t(s->m_op)];
    if (value != value_output(s->m_op))
        b.fail(p.pointer("output"),
               value ? "operation '" + name +
                           "' has no Value output (Cycles gives 0 there): give output \"vector\""
                     : "operation '" + name +
                           "' gives the Value output only (its Vector is 0): give output "
                           "\"value\"");
    // A number texture computes with grey vectors (every operation keeps them grey), unless
    // it reads a channel of the result or the Value of colours.
    const bool colours = b.color || !b.desc.channel.empty() || value;
    s->m_a = p.input("a", colours);
    s->m_b = p.input("b", colours);
    s->m_c = p.input("c", colours);
    s->m_s = p.input("scale", false);
    Interval r[3];
    vector_math_range(*s, r);
    Rgb lo, hi;
    for (int k = 0; k < 3; ++k) lo[k] = float(r[k].lo), hi[k] = float(r[k].hi);
    return make_composite(b, kVectorMathTexture, s, lo, hi, p.reads(), "operation '" + name + "'");
}

}  // namespace

const TextureKindDef kVectorMathTexture{
    "vector_math",
    "Blender's Vector Math node per hit: `operation` of the vectors a, b, c (colours, numbers "
    "or textures) and the number `scale`, as Cycles 3.4 (composite: no coordinates)",
    {
        {"operation", ParamType::String, 0, "add", 0, 0, false, kOperations,
         "Blender's operation, lower case (CROSS_PRODUCT: cross_product)"},
        {"output", ParamType::String, 0, "vector", 0, 0, false, kOutputs,
         "the node's output: `value` for dot_product, distance and length (grey), else "
         "`vector`"},
        {"a",
         ParamType::Color,
         0,
         {},
         0,
         0,
         false,
         {},
         "the first Vector (default 0)",
         TextureParamForm::Input,
         Rgb(0.f)},
        {"b",
         ParamType::Color,
         0,
         {},
         0,
         0,
         false,
         {},
         "the second Vector (wrap: the Max; faceforward: the Incident; default 0)",
         TextureParamForm::Input,
         Rgb(0.f)},
        {"c",
         ParamType::Color,
         0,
         {},
         0,
         0,
         false,
         {},
         "the third Vector (wrap: the Min; faceforward: the Reference; default 0)",
         TextureParamForm::Input,
         Rgb(0.f)},
        {"scale",
         ParamType::Number,
         1,
         {},
         -1e30,
         1e30,
         false,
         {},
         "the Scale (refract: the IOR)",
         TextureParamForm::Input},
    },
    true,
    build_vector_math,
    true,
};

}  // namespace facet::render
