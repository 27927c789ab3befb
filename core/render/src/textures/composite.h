// Private to facet_render: what the composite texture kinds share (texture.h conventions,
// "Composite kinds"; texture_kinds.h: math, vector_math, mix_rgb, color_ramp). A composite
// reads no point of its own: each Input parameter is a constant or another texture evaluated
// at the same hit, and the kind's function of those values (Blender's node, as Cycles 3.4
// evaluates it, in float) is its value, times the texture's scale.
//
// Value ranges: every texture states the smallest and largest value it takes (Texture::
// min_value, max_value; build_scene validates material parameters at them and clamps to them).
// A composite bounds its value from its inputs' ranges by interval arithmetic (Interval below),
// conservatively; a value that cannot be bounded (a division by an input whose range holds 0,
// an exponential of an unbounded one, ...) is an error naming the texture's pointer.
#pragma once

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>

#include "procedural.h"

namespace facet::render {

// A closed interval [lo, hi] of doubles (infinite ends: unbounded).
struct Interval {
    double lo = 0.0, hi = 0.0;
    static Interval of(double v) { return {v, v}; }
    // The smallest interval holding every value listed.
    static Interval hull(std::initializer_list<double> v) {
        return {*std::min_element(v.begin(), v.end()), *std::max_element(v.begin(), v.end())};
    }
    Interval join(const Interval& o) const { return {std::min(lo, o.lo), std::max(hi, o.hi)}; }
    bool contains(double v) const { return lo <= v && v <= hi; }
    bool finite() const { return std::isfinite(lo) && std::isfinite(hi); }
    Interval clamped(double a, double b) const {
        return {std::clamp(lo, a, b), std::clamp(hi, a, b)};
    }
};

inline Interval operator+(const Interval& a, const Interval& b) {
    return {a.lo + b.lo, a.hi + b.hi};
}
inline Interval operator-(const Interval& a, const Interval& b) {
    return {a.lo - b.hi, a.hi - b.lo};
}
inline Interval operator-(const Interval& a) {
    return {-a.hi, -a.lo};
}
// A product of an infinite and a zero end is unbounded (never a NaN end).
inline Interval operator*(const Interval& a, const Interval& b) {
    const double p[4] = {a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi};
    for (double x : p)
        if (std::isnan(x)) return {-INFINITY, INFINITY};
    return {std::min({p[0], p[1], p[2], p[3]}), std::max({p[0], p[1], p[2], p[3]})};
}

// One Input parameter of a composite kind: a constant, or a texture evaluated at the hit.
class CompositeInput {
  public:
    Rgb eval(const TexturePoint& p) const { return m_texture ? m_texture->eval(p) : m_constant; }
    float number(const TexturePoint& p) const {
        return m_texture ? m_texture->eval(p).r : m_constant.r;
    }
    // The range of channel c (0 for a number input).
    Interval range(int c = 0) const { return {double(m_lo[c]), double(m_hi[c])}; }
    bool is_constant() const { return !m_texture; }

    std::optional<Texture> m_texture;
    Rgb m_constant{0.f};
    Rgb m_lo{0.f}, m_hi{0.f};
};

// A composite kind's evaluation: its value times the texture's scale.
class CompositeSource : public TextureSource {
  public:
    Rgb eval(const TexturePoint& p) const final { return value(p) * m_scale; }
    // The kind's value at the hit (before the scale).
    virtual Rgb value(const TexturePoint& p) const = 0;

    Rgb m_scale{1.f};
};

// Reads the composite kind's parameters (check_texture_params first) and its inputs.
class CompositeParams : public ProceduralParams {
  public:
    CompositeParams(TextureBuild& b, const TextureKindDef& kind);
    // Input parameter `name`: its texture (built as a colour when `color`, else a number) or
    // its constant (a number as grey; a colour given to a number input is an error).
    CompositeInput input(std::string_view name, bool color) const;
    // What the inputs built so far read (TextureInput bits).
    unsigned reads() const { return m_reads; }

  private:
    TextureBuild& m_b;
    const TextureKindDef& m_kind;
    mutable unsigned m_reads = 0;
};

// Blender's Math node (math.cpp; vector_math applies it per component): the index of
// operation `name` (lower case; -1: none), its value as Cycles' svm_math in float, and a
// conservative range of that value over the inputs' ranges (infinite ends: unbounded).
int math_operation(std::string_view name);
float math_operation_value(int op, float a, float b, float c);
Interval math_operation_range(int op, Interval a, Interval b, Interval c);

// The texture of a composite kind: `source` with the texture's scale, its value range
// [lo, hi] per channel (before the scale; an unbounded one is an error, `why` says which
// operation), reading what its inputs read. A number texture (TextureBuild::color false) must
// have a grey range.
Texture make_composite(TextureBuild& b, const TextureKindDef& kind,
                       std::shared_ptr<CompositeSource> source, Rgb lo, Rgb hi, unsigned reads,
                       const std::string& why);

}  // namespace facet::render
