// Batched evaluation of a microfacet lobe: f and pdf for many (wo, wi) pairs at once, from
// structure-of-arrays inputs, for callers that hold many queries (reflectance tables, film-space
// shading passes, benchmarks, the Blender/POV-Ray bridges filling whole buffers).
//
// Conventions: facet/bxdf.h and facet/microfacet.h (local frame, z = shading normal, wo toward the
// viewer, both directions unit and pointing away from the surface; f without the cosine; pdf per
// unit solid angle of wi). Element k of the output equals MicrofacetReflection::f(wo[k], wi[k])
// (resp. pdf) of the lobe the batch was built from, bit for bit: the vectorised kernel performs
// the same IEEE operations in the same order as the scalar GGX path (Heitz 2014 eq. 99 in the
// form G2 / (4 cos_o cos_i) = 1 / (2 (A_o cos_i + A_i cos_o)); Walter et al. 2007 eq. 33 for D),
// and the file is compiled without FMA contraction.
//
// Which lobes are vectorised: GGX (isotropic or anisotropic) without energy compensation, with
// any Fresnel (Constant and Schlick inside the vector loop; dielectric and conductor by a scalar
// Fresnel pass over each block). Everything else (Beckmann, Blinn, compensated lobes) runs the
// scalar model per element: same results, no speed-up. Smooth (mirror) lobes give f = pdf = 0,
// as the scalar delta-lobe convention says. vectorised() tells which path a batch takes.
//
// f_single_fixed: the single-scattering term f_single (without the compensation lobe) of one
// fixed direction against n free ones, for the reflectance quadrature (facet/reflectance.h),
// which holds one direction and integrates over the other. GGX (compensated or not): the
// vectorised GGX kernel, bit for bit f_single. Blinn: a vectorised kernel on the same formulas
// (core/src/microfacet_formulas.h) with polynomial exp / log / log1p in place of libm's, equal
// to f_single to float precision (tested: within 16 ulp times 1 + |E|, E the log-space
// exponent of D or Lambda, the conditioning of exp(E) itself; ~4.5 ulp measured).
// Beckmann: the scalar model per element with Lambda of the fixed direction computed once, bit
// for bit.
//
// The arrays may not alias the outputs; n may be 0. No allocation, no exceptions.
#pragma once

#include <cstddef>

#include "facet/microfacet.h"

namespace facet {

// Read-only structure-of-arrays view of n directions.
struct Vec3Soa {
    const float* x;
    const float* y;
    const float* z;
};

// Writable structure-of-arrays view of n RGB values.
struct RgbSoa {
    float* r;
    float* g;
    float* b;
};

class MicrofacetBatch {
  public:
    explicit MicrofacetBatch(const MicrofacetReflection& lobe);

    // out[k] = lobe.f(wo[k], wi[k]) for k < n.
    void f(std::size_t n, Vec3Soa wo, Vec3Soa wi, RgbSoa out) const;
    // out[k] = lobe.pdf(wo[k], wi[k]) for k < n.
    void pdf(std::size_t n, Vec3Soa wo, Vec3Soa wi, float* out) const;

    // out[k] = lobe.f_single(fixed, w[k]) when fixed_is_wo, else lobe.f_single(w[k], fixed)
    // (see the header comment for the precision).
    void f_single_fixed(std::size_t n, const Vec3& fixed, bool fixed_is_wo, Vec3Soa w,
                        RgbSoa out) const;

    // True when f / pdf run the vectorised GGX kernel (see the header comment).
    bool vectorised() const { return m_vectorised; }

  private:
    MicrofacetReflection m_lobe;  // a copy: the batch owns no reference into the caller's data
    bool m_vectorised = false;
    bool m_smooth = false;
    bool m_fresnel_in_loop = false;  // Constant or Schlick: F = a + b (1 - c)^5 in the loop
    float m_ax = 1.f, m_ay = 1.f, m_norm = 0.f;
    // (scale F) s for n elements from s and the Fresnel cosine c (in the loop or scalar).
    void apply_fresnel(std::size_t n, const float* s, const float* c, RgbSoa out) const;
    Rgb m_fa{0.f}, m_fb{0.f};  // F = m_fa + m_fb m5 (Schlick: F0, 1 - F0; Constant: value, 0)
};

}  // namespace facet
