// Texture kind "voronoi": Blender 3.4's Voronoi Texture node (Cycles' svm_voronoi; Worley 1996
// cellular noise with Cycles' hash, cycles_noise.h) in 1-4 dimensions.
//
// The point x (procedural.h) times Scale (W x Scale the 4th or, in 1D, only coordinate) lies in
// unit cell c = floor(x); each cell c' holds one feature point c' + Randomness h(c') (h the
// hash of the cell's corner to [0, 1)^n). Searching the 3^n cells around c (5^n for Smooth F1):
//  - f1 / f2: the distance to the nearest / second nearest point, Color the hash of its cell;
//  - smooth_f1: Inigo Quilez's smooth minimum of the distances (and colours), with the
//    smoothness k = clamp(Smoothness / 2, 0, 1/2): h = smoothstep(0, 1, 1/2 + (d_sum - d) / 2k),
//    d_sum <- mix(d_sum, d, h) - k h (1 - h);
//  - distance_to_edge: the distance to the nearest bisector between the nearest point and the
//    others (Euclidean);
//  - n_sphere_radius: half the distance from the nearest point to its own nearest point.
// Distances: euclidean, manhattan, chebychev, minkowski (exponent e: (sum |d_i|^e)^(1/e)); in
// 1D every metric is |d|. Randomness is clamped to [0, 1].
#include "cycles_noise.h"
#include "procedural.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace facet::render {

namespace {

using cycles::vec2;
using cycles::vec3;
using cycles::vec4;

enum class Feature { F1, F2, SmoothF1, DistanceToEdge, NSphereRadius };
enum class Metric { Euclidean, Manhattan, Chebychev, Minkowski };

// The feature point's offset in cell c (Cycles' hash_floatN_to_floatN).
inline float cell_point(float c) {
    return cycles::hash_float(c);
}
inline vec2 cell_point(vec2 c) {
    return cycles::hash_vec2(c);
}
inline vec3 cell_point(vec3 c) {
    return cycles::hash_vec3(c);
}
inline vec4 cell_point(vec4 c) {
    return cycles::hash_vec4(c);
}

template <class P>
float dot_n(P a, P b) {
    float s = 0.f;
    for (int i = 0; i < P::length(); ++i) s += a[i] * b[i];
    return s;
}
template <class P>
float length_n(P a) {
    return std::sqrt(dot_n(a, a));
}

// Cycles' smoothstep(0, 1, x).
float smoothstep01(float x) {
    if (x < 0.f) return 0.f;
    if (x >= 1.f) return 1.f;
    return (3.f - 2.f * x) * (x * x);
}

struct VoronoiResult {
    float distance = 0.f;
    vec3 color{0.f};
    float radius = 0.f;
};

class VoronoiSource final : public ProceduralSource {
  public:
    int m_dimensions = 3;
    float m_scale_in = 5.f, m_smoothness = 0.5f, m_exponent = 0.5f, m_randomness = 1.f, m_w = 0.f;
    Feature m_feature = Feature::F1;
    Metric m_metric = Metric::Euclidean;
    int m_output = 0;  // distance, color, radius

    template <class P>
    float distance(P a, P b) const {
        switch (m_metric) {
            case Metric::Manhattan: {
                float s = 0.f;
                for (int i = 0; i < P::length(); ++i) s += std::fabs(a[i] - b[i]);
                return s;
            }
            case Metric::Chebychev: {
                float s = 0.f;
                for (int i = 0; i < P::length(); ++i) s = std::max(s, std::fabs(a[i] - b[i]));
                return s;
            }
            case Metric::Minkowski: {
                float s = 0.f;
                for (int i = 0; i < P::length(); ++i)
                    s += std::pow(std::fabs(a[i] - b[i]), m_exponent);
                return std::pow(s, 1.f / m_exponent);
            }
            case Metric::Euclidean:
            default:
                return length_n(a - b);
        }
    }

    // The k-th cell offset of the (2r + 1)^n cells around the cell, x fastest.
    template <class P>
    static P offset(int k, int r) {
        P o;
        for (int i = 0; i < P::length(); ++i) {
            o[i] = float(k % (2 * r + 1) - r);
            k /= 2 * r + 1;
        }
        return o;
    }
    template <class P>
    static int cells(int r) {
        int n = 1;
        for (int i = 0; i < P::length(); ++i) n *= 2 * r + 1;
        return n;
    }

    template <class P>
    VoronoiResult voronoi(P coord) const {
        const P cell = glm::floor(coord);
        const P local = coord - cell;
        VoronoiResult out;
        auto point_in = [&](P o) { return o + cell_point(cell + o) * m_randomness; };
        if (m_feature == Feature::F1 || m_feature == Feature::F2) {
            float d1 = FLT_MAX, d2 = FLT_MAX;
            P o1(0.f), o2(0.f);
            for (int k = 0; k < cells<P>(1); ++k) {
                const P o = offset<P>(k, 1);
                const float d = distance(point_in(o), local);
                if (d < d1) {
                    d2 = d1, o2 = o1;
                    d1 = d, o1 = o;
                } else if (d < d2) {
                    d2 = d, o2 = o;
                }
            }
            const bool f1 = m_feature == Feature::F1;
            out.distance = f1 ? d1 : d2;
            out.color = cycles::hash_vec3(cell + (f1 ? o1 : o2));
        } else if (m_feature == Feature::SmoothF1) {
            float sd = 0.f, h = -1.f;
            vec3 sc(0.f);
            for (int k = 0; k < cells<P>(2); ++k) {
                const P o = offset<P>(k, 2);
                const float d = distance(point_in(o), local);
                h = h == -1.f ? 1.f : smoothstep01(0.5f + 0.5f * (sd - d) / m_smoothness);
                float correction = m_smoothness * h * (1.f - h);
                sd = cycles::lerp(sd, d, h) - correction;
                correction /= 1.f + 3.f * m_smoothness;
                const vec3 c = cycles::hash_vec3(cell + o);
                sc = sc + h * (c - sc) - correction;
            }
            out.distance = sd;
            out.color = sc;
        } else if (m_feature == Feature::DistanceToEdge) {
            P closest(0.f);
            float best = FLT_MAX;
            for (int k = 0; k < cells<P>(1); ++k) {
                const P v = point_in(offset<P>(k, 1)) - local;
                const float d = dot_n(v, v);
                if (d < best) best = d, closest = v;
            }
            best = FLT_MAX;
            for (int k = 0; k < cells<P>(1); ++k) {
                const P v = point_in(offset<P>(k, 1)) - local;
                const P perp = v - closest;
                if (dot_n(perp, perp) > 0.0001f) {
                    const float e = dot_n((closest + v) / 2.f, perp / length_n(perp));
                    best = std::min(best, e);
                }
            }
            out.distance = best;
        } else {
            P closest(0.f), closest_offset(0.f);
            float best = FLT_MAX;
            for (int k = 0; k < cells<P>(1); ++k) {
                const P o = offset<P>(k, 1);
                const P pt = point_in(o);
                const float d = length_n(pt - local);
                if (d < best) best = d, closest = pt, closest_offset = o;
            }
            best = FLT_MAX;
            P to_closest(0.f);
            for (int k = 0; k < cells<P>(1); ++k) {
                const P o = offset<P>(k, 1);
                if (o == P(0.f)) continue;
                const P pt = point_in(o + closest_offset);
                const float d = length_n(closest - pt);
                if (d < best) best = d, to_closest = pt;
            }
            out.radius = length_n(to_closest - closest) / 2.f;
        }
        return out;
    }

    // 1D (every metric is |d|).
    VoronoiResult voronoi(float coord) const {
        const float cell = std::floor(coord), local = coord - cell;
        VoronoiResult out;
        auto point_in = [&](float o) { return o + cycles::hash_float(cell + o) * m_randomness; };
        if (m_feature == Feature::F1 || m_feature == Feature::F2) {
            float d1 = FLT_MAX, d2 = FLT_MAX, o1 = 0.f, o2 = 0.f;
            for (int i = -1; i <= 1; ++i) {
                const float o = float(i);
                const float d = std::fabs(point_in(o) - local);
                if (d < d1) {
                    d2 = d1, o2 = o1;
                    d1 = d, o1 = o;
                } else if (d < d2) {
                    d2 = d, o2 = o;
                }
            }
            const bool f1 = m_feature == Feature::F1;
            out.distance = f1 ? d1 : d2;
            out.color = cycles::hash_vec3(cell + (f1 ? o1 : o2));
        } else if (m_feature == Feature::SmoothF1) {
            float sd = 0.f, h = -1.f;
            vec3 sc(0.f);
            for (int i = -2; i <= 2; ++i) {
                const float o = float(i);
                const float d = std::fabs(point_in(o) - local);
                h = h == -1.f ? 1.f : smoothstep01(0.5f + 0.5f * (sd - d) / m_smoothness);
                float correction = m_smoothness * h * (1.f - h);
                sd = cycles::lerp(sd, d, h) - correction;
                correction /= 1.f + 3.f * m_smoothness;
                const vec3 c = cycles::hash_vec3(cell + o);
                sc = sc + h * (c - sc) - correction;
            }
            out.distance = sd;
            out.color = sc;
        } else if (m_feature == Feature::DistanceToEdge) {
            const float mid = point_in(0.f), left = point_in(-1.f), right = point_in(1.f);
            out.distance = std::min(std::fabs((mid + left) / 2.f - local),
                                    std::fabs((mid + right) / 2.f - local));
        } else {
            float closest = 0.f, closest_offset = 0.f, best = FLT_MAX;
            for (int i = -1; i <= 1; ++i) {
                const float pt = point_in(float(i));
                const float d = std::fabs(pt - local);
                if (d < best) best = d, closest = pt, closest_offset = float(i);
            }
            best = FLT_MAX;
            float to_closest = 0.f;
            for (int i = -1; i <= 1; ++i) {
                if (i == 0) continue;
                const float pt = point_in(float(i) + closest_offset);
                const float d = std::fabs(closest - pt);
                if (d < best) best = d, to_closest = pt;
            }
            out.radius = std::fabs(to_closest - closest) / 2.f;
        }
        return out;
    }

    Rgb pattern(const Vec3& x) const override {
        const Vec3 v = x * m_scale_in;
        const float w = m_w * m_scale_in;
        VoronoiResult r;
        switch (m_dimensions) {
            case 1:
                r = voronoi(w);
                break;
            case 2:
                r = voronoi(vec2(v.x, v.y));
                break;
            case 4:
                r = voronoi(vec4(v.x, v.y, v.z, w));
                break;
            default:
                r = voronoi(vec3(v));
                break;
        }
        if (m_output == 1) return Rgb(r.color);
        return Rgb(m_output == 2 ? r.radius : r.distance);
    }
};

Texture build_voronoi(TextureBuild& b) {
    auto s = std::make_shared<VoronoiSource>();
    const ProceduralParams p(b, kVoronoiTexture);
    // Validate first (make_procedural), then read.
    Texture checked = make_procedural(b, kVoronoiTexture, s, Rgb(0.f), Rgb(1.f));
    s->m_dimensions = int(p.number("dimensions"));
    s->m_scale_in = float(p.number("scale"));
    s->m_smoothness = std::clamp(float(p.number("smoothness")) / 2.f, 0.f, 0.5f);
    s->m_exponent = float(p.number("exponent"));
    s->m_randomness = std::clamp(float(p.number("randomness")), 0.f, 1.f);
    s->m_w = float(p.number("w"));
    s->m_feature = Feature(p.choice("feature"));
    s->m_metric = Metric(p.choice("distance"));
    s->m_output = p.choice("output");
    const bool radius = s->m_feature == Feature::NSphereRadius;
    if (radius != (s->m_output == 2) ||
        (s->m_output == 1 && s->m_feature == Feature::DistanceToEdge))
        b.fail(p.pointer("output"),
               radius ? "n_sphere_radius has the output radius only"
                      : "the feature has no output '" +
                            std::string(s->m_output == 1 ? "color" : "radius") + "'");
    if (s->m_output == 1) return checked;  // colours in [0, 1]
    // Distances: every coordinate of a feature point is within 2 cells of the point (1 + the
    // randomness), so a distance is at most the metric's length of (2, ..., 2): 2 n^(1/e)
    // (Minkowski; e = 2 Euclidean, 1 Manhattan, infinity Chebychev); the smooth minimum is
    // below the plain one.
    const int n = s->m_dimensions;
    const double e = s->m_metric == Metric::Euclidean   ? 2.0
                     : s->m_metric == Metric::Manhattan ? 1.0
                     : s->m_metric == Metric::Chebychev ? INFINITY
                                                        : double(s->m_exponent);
    const double bound = n == 1 || radius || s->m_feature == Feature::DistanceToEdge
                             ? 2.0 * std::sqrt(double(n))
                             : 2.0 * std::pow(double(n), 1.0 / e);
    if (!(bound < 1e30)) b.fail(p.pointer("exponent"), "must be > 0");
    return make_procedural(b, kVoronoiTexture, s, Rgb(0.f), Rgb(float(bound)));
}

}  // namespace

const TextureKindDef kVoronoiTexture{
    "voronoi",
    "Blender's Voronoi Texture: cellular noise (Cycles 3.4)",
    {
        {"dimensions", ParamType::Number, 3, {}, 1, 4, true, {}, "1, 2, 3 or 4 (W the 4th)"},
        {"scale", ParamType::Number, 5, {}, -1e30, 1e30, false, {}, "Scale"},
        {"smoothness", ParamType::Number, 1, {}, -1e30, 1e30, false, {}, "Smoothness (smooth_f1)"},
        {"exponent", ParamType::Number, 0.5, {}, 1e-6, 1e30, false, {}, "Exponent (minkowski)"},
        {"randomness", ParamType::Number, 1, {}, -1e30, 1e30, false, {}, "Randomness"},
        {"w", ParamType::Number, 0, {}, -1e30, 1e30, false, {}, "W (1D and 4D)"},
        {"feature",
         ParamType::String,
         0,
         "f1",
         0,
         0,
         false,
         {"f1", "f2", "smooth_f1", "distance_to_edge", "n_sphere_radius"},
         "Feature"},
        {"distance",
         ParamType::String,
         0,
         "euclidean",
         0,
         0,
         false,
         {"euclidean", "manhattan", "chebychev", "minkowski"},
         "Distance metric"},
        {"output",
         ParamType::String,
         0,
         "distance",
         0,
         0,
         false,
         {"distance", "color", "radius"},
         kOutputDoc},
    },
    true,
    build_voronoi,
};

}  // namespace facet::render
