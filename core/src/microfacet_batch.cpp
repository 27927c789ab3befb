// Batched microfacet evaluation; see facet/microfacet_batch.h for the conventions.
//
// The GGX kernel is a straight loop over blocks of kBlock elements with no calls and no
// data-dependent branches (below-horizon pairs are masked with a select at the end), so the
// compiler vectorises it. The kernels are compiled twice (target_clones): for the baseline
// x86-64 ISA and for AVX2; the loader picks the AVX2 copy on machines that have it. This file
// is built with -fno-math-errno (lets sqrt vectorise; errno is never read), -fno-trapping-math
// (lets the masked lanes' divisions be computed; FP exceptions are never enabled) and
// -ffp-contract=off (no FMA: results stay identical to the scalar path). No -ffast-math.
#include "facet/microfacet_batch.h"
#include "facet/target_clones.h"

#include <algorithm>

namespace facet {

namespace {

constexpr std::size_t kBlock = 256;

struct GgxConstants {
    float ax, ay, inv_ax, inv_ay, norm;
};

// The lobe's constants; 1 / alpha is computed as MicrofacetDistribution::ggx does, so that the
// kernel's products hx (1 / ax) are the scalar path's bit for bit.
GgxConstants ggx_constants(float ax, float ay, float norm) {
    return {ax, ay, 1.f / ax, 1.f / ay, norm};
}

// The terms shared by f and pdf for one pair, with the operations and order of
// MicrofacetReflection::evaluate_ggx: h = wo + wi, |h|^2, D = norm (|h|^2 / Q)^2 with
// Q = hz^2 + (hx/ax)^2 + (hy/ay)^2 (as hx (1/ax)) (Walter et al. 2007 eq. 33 from the unnormalised
// h), and A_o = sqrt(cos_o^2 + (ax x_o)^2 + (ay y_o)^2).
struct GgxPair {
    float hx, hy, hz, len2, d, a_o;
};
__attribute__((always_inline)) inline GgxPair ggx_pair(float ox, float oy, float oz, float ix,
                                                       float iy, float iz, GgxConstants k) {
    GgxPair p;
    p.hx = ox + ix, p.hy = oy + iy, p.hz = oz + iz;
    p.len2 = p.hx * p.hx + p.hy * p.hy + p.hz * p.hz;
    float sx = p.hx * k.inv_ax, sy = p.hy * k.inv_ay;
    float q = p.hz * p.hz + sx * sx + sy * sy;
    p.d = k.norm * (p.len2 / q) * (p.len2 / q);
    p.a_o = std::sqrt(oz * oz + (k.ax * ox) * (k.ax * ox) + (k.ay * oy) * (k.ay * oy));
    return p;
}

// Per element: s = D G2 / (4 cos_o cos_i) = D / (2 (A_o cos_i + A_i cos_o)) (Heitz 2014
// eq. 99 rearranged) and the Fresnel cosine c = <wo, wm>, clamped to [0, 1] as Fresnel::eval
// does.
FACET_TARGET_CLONES
void ggx_f_block(std::size_t n, const float* __restrict ox, const float* __restrict oy,
                 const float* __restrict oz, const float* __restrict ix, const float* __restrict iy,
                 const float* __restrict iz, GgxConstants k, float* __restrict s_out,
                 float* __restrict c_out) {
    for (std::size_t j = 0; j < n; ++j) {
        float cos_o = oz[j], cos_i = iz[j];
        GgxPair p = ggx_pair(ox[j], oy[j], cos_o, ix[j], iy[j], cos_i, k);
        float a_i = std::sqrt(cos_i * cos_i + (k.ax * ix[j]) * (k.ax * ix[j]) +
                              (k.ay * iy[j]) * (k.ay * iy[j]));
        float s = p.d / (2.f * (p.a_o * cos_i + a_i * cos_o));
        float c = (ox[j] * p.hx + oy[j] * p.hy + cos_o * p.hz) / std::sqrt(p.len2);
        c = c < 0.f ? 0.f : (1.f < c ? 1.f : c);
        bool above = (cos_o > 0.f) & (cos_i > 0.f);  // & not &&: no branch, so it vectorises
        // Masked lanes get s = 0 and c = 0 (not NaN from wo = -wi): F stays finite, f = 0.
        s_out[j] = above ? s : 0.f;
        c_out[j] = above ? c : 0.f;
    }
}

// out = (scale F) s with F = fa + fb (1 - c)^5 (Schlick form; Constant has fb = 0), in the
// order of the scalar path: (scale * F) * s.
FACET_TARGET_CLONES
void schlick_block(std::size_t n, const float* __restrict s, const float* __restrict c, Rgb scale,
                   Rgb fa, Rgb fb, float* __restrict r, float* __restrict g, float* __restrict b) {
    for (std::size_t j = 0; j < n; ++j) {
        float m = 1.f - c[j];
        float m5 = (m * m) * (m * m) * m;
        r[j] = scale.r * (fa.r + fb.r * m5) * s[j];
        g[j] = scale.g * (fa.g + fb.g * m5) * s[j];
        b[j] = scale.b * (fa.b + fb.b * m5) * s[j];
    }
}

// Visible-normal pdf G1(wo) D / (4 cos_o) = D / (2 (A_o + cos_o)) (see evaluate_ggx).
FACET_TARGET_CLONES
void ggx_pdf_block(std::size_t n, const float* __restrict ox, const float* __restrict oy,
                   const float* __restrict oz, const float* __restrict ix,
                   const float* __restrict iy, const float* __restrict iz, GgxConstants k,
                   float* __restrict out) {
    for (std::size_t j = 0; j < n; ++j) {
        GgxPair p = ggx_pair(ox[j], oy[j], oz[j], ix[j], iy[j], iz[j], k);
        float pdf = p.d / (2.f * (p.a_o + oz[j]));
        out[j] = ((oz[j] > 0.f) & (iz[j] > 0.f)) ? pdf : 0.f;
    }
}

Vec3 at(Vec3Soa v, std::size_t k) {
    return {v.x[k], v.y[k], v.z[k]};
}

Vec3Soa offset(Vec3Soa v, std::size_t k) {
    return {v.x + k, v.y + k, v.z + k};
}

}  // namespace

MicrofacetBatch::MicrofacetBatch(const MicrofacetReflection& lobe) : m_lobe(lobe) {
    const MicrofacetDistribution& d = lobe.distribution();
    m_smooth = d.effectively_smooth();
    m_vectorised = d.kind() == DistributionKind::GGX && !m_smooth && !lobe.energy_compensation();
    m_ax = d.alpha_x();
    m_ay = d.alpha_y();
    m_norm = d.D(Vec3(0.f, 0.f, 1.f));  // = 1 / (pi ax ay), the same float the scalar path uses
    const Fresnel& fr = lobe.fresnel();
    if (fr.kind() == Fresnel::Kind::Schlick) {
        m_fresnel_in_loop = true;
        m_fa = fr.eta();  // F0
        m_fb = Rgb(1.f) - fr.eta();
    } else if (fr.kind() == Fresnel::Kind::Constant) {
        m_fresnel_in_loop = true;
        m_fa = fr.eta();  // the constant value
        m_fb = Rgb(0.f);
    }
}

void MicrofacetBatch::f(std::size_t n, Vec3Soa wo, Vec3Soa wi, RgbSoa out) const {
    if (m_smooth) {
        std::fill_n(out.r, n, 0.f), std::fill_n(out.g, n, 0.f), std::fill_n(out.b, n, 0.f);
        return;
    }
    if (!m_vectorised) {
        for (std::size_t k = 0; k < n; ++k) {
            Rgb v = m_lobe.f(at(wo, k), at(wi, k));
            out.r[k] = v.r, out.g[k] = v.g, out.b[k] = v.b;
        }
        return;
    }
    const GgxConstants kc = ggx_constants(m_ax, m_ay, m_norm);
    float s[kBlock], c[kBlock];
    for (std::size_t k0 = 0; k0 < n; k0 += kBlock) {
        std::size_t m = std::min(kBlock, n - k0);
        Vec3Soa o = offset(wo, k0), i = offset(wi, k0);
        ggx_f_block(m, o.x, o.y, o.z, i.x, i.y, i.z, kc, s, c);
        if (m_fresnel_in_loop) {
            schlick_block(m, s, c, m_lobe.scale(), m_fa, m_fb, out.r + k0, out.g + k0, out.b + k0);
        } else {
            // Dielectric / conductor Fresnel: scalar per element (exact, double inside).
            for (std::size_t j = 0; j < m; ++j) {
                Rgb v = m_lobe.scale() * m_lobe.fresnel().eval(c[j]) * s[j];
                out.r[k0 + j] = v.r, out.g[k0 + j] = v.g, out.b[k0 + j] = v.b;
            }
        }
    }
}

void MicrofacetBatch::pdf(std::size_t n, Vec3Soa wo, Vec3Soa wi, float* out) const {
    if (m_smooth) {
        std::fill_n(out, n, 0.f);
        return;
    }
    if (!m_vectorised) {
        for (std::size_t k = 0; k < n; ++k) out[k] = m_lobe.pdf(at(wo, k), at(wi, k));
        return;
    }
    const GgxConstants kc = ggx_constants(m_ax, m_ay, m_norm);
    ggx_pdf_block(n, wo.x, wo.y, wo.z, wi.x, wi.y, wi.z, kc, out);
}

}  // namespace facet
