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
#include <bit>
#include <cstdint>

#include "microfacet_formulas.h"

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

// Branch-free float exp, log and log1p for the vectorised Blinn kernel: the Cephes
// single-precision polynomials (S. L. Moshier, Cephes Math Library: expf, logf), ~1 ulp from
// libm's on their domains, and log1p(t) = log(u) t / (u - 1), u = 1 + t (Goldberg 1991, thm. 4),
// a few ulp. Only what the Blinn formulas need: exp over the whole float range (0 below the
// denormals, inf above 88.72), log of positive floats (denormals included) and +inf, log1p of
// t >= 0 and +inf. NaN gives some number (the kernel's guards discard those lanes).
struct FastMath {
    static float exp(float x) {
        const bool under = !(x > -104.f);  // and NaN: below the smallest denormal
        const bool over = x > 88.7228f;
        x = (under | over) ? 0.f : x;
        const float n = std::floor(x * 1.44269504f + 0.5f);  // x = n ln2 + r, |r| <= ln2 / 2
        float r = x - n * 0.693359375f;                      // ln2 in two parts: exact product
        r = r - n * -2.12194440e-4f;
        float p = ((((1.9875691500e-4f * r + 1.3981999507e-3f) * r + 8.3334519073e-3f) * r +
                    4.1665795894e-2f) *
                       r +
                   1.6666665459e-1f) *
                      r +
                  5.0000001201e-1f;
        p = p * (r * r) + r + 1.f;
        // 2^n, n in [-150, 128], as two normal factors so that denormal results come out right.
        const std::int32_t ni = std::int32_t(n), n1 = ni >> 1, n2 = ni - n1;
        const float s1 = std::bit_cast<float>((n1 + 127) << 23);
        const float s2 = std::bit_cast<float>((n2 + 127) << 23);
        const float y = p * s1 * s2;
        return under ? 0.f : (over ? kInfinity : y);
    }
    static float log(float x) {
        const bool tiny = x < 1.17549435e-38f;  // denormal: scale into the normal range
        const float xs = tiny ? x * 8388608.f : x;
        const std::uint32_t bits = std::bit_cast<std::uint32_t>(xs);
        std::int32_t e = std::int32_t((bits >> 23) & 0xffu) - 126;  // xs = m 2^e, m in [1/2, 1)
        const float m = std::bit_cast<float>((bits & 0x807fffffu) | 0x3f000000u);
        const bool low = m < 0.707106781186547524f;  // f = m - 1 in [sqrt(1/2) - 1, sqrt(2) - 1)
        e = low ? e - 1 : e;
        const float f = low ? m + m - 1.f : m - 1.f;
        const float z = f * f;
        float y = ((((((((7.0376836292e-2f * f - 1.1514610310e-1f) * f + 1.1676998740e-1f) * f -
                        1.2420140846e-1f) *
                           f +
                       1.4249322787e-1f) *
                          f -
                      1.6668057665e-1f) *
                         f +
                     2.0000714765e-1f) *
                        f -
                    2.4999993993e-1f) *
                       f +
                   3.3333331174e-1f) *
                  f * z;
        const float fe = float(e) - (tiny ? 23.f : 0.f);
        y += -2.12194440e-4f * fe;
        y += -0.5f * z;
        const float r = (f + y) + 0.693359375f * fe;
        return x == kInfinity ? kInfinity : r;
    }
    static float log1p(float t) {
        const float u = 1.f + t, d = u - 1.f;
        const float r = log(u) * (t / d);
        return d == 0.f ? t : (u == kInfinity ? kInfinity : r);
    }
    static float max(float a, float b) { return a > b ? a : b; }  // fmax(NaN, b) = b as well
};

struct BlinnConstants {
    float ax, ay, log_norm, half_nu_p2, half_nu_m1, k, s, zero_lambda_e;
    const float* rho;
    float fx, fy, fz, lam_fixed;  // the fixed direction and its Lambda
};

// f_single of Blinn for one fixed direction and n <= kBlock free ones, the operations of
// MicrofacetReflection::evaluate / MicrofacetDistribution::D and lambda (the same formulas,
// FastMath for libm): s = D G / (4 cos_o cos_i) and the Fresnel cosine c = <wo, wm>, clamped
// to [0, 1]; 0 where the scalar path returns 0 (below the horizon, wo + wi = 0, D's guards).
// Three loops: the rho table's reads sit in a loop of their own (GCC does not vectorise the
// whole loop around them: the clamped index becomes a select of addresses, not a gather).
template <bool fixed_is_wo>
__attribute__((always_inline)) inline void blinn_fixed_loop(
    std::size_t n, const float* __restrict wx, const float* __restrict wy,
    const float* __restrict wz, BlinnConstants k, float* __restrict s_out,
    float* __restrict c_out) {
    float d_a[kBlock], e_a[kBlock], mu_a[kBlock], v_a[kBlock], rho_a[kBlock];
    for (std::size_t j = 0; j < n; ++j) {
        const float x = wx[j], y = wy[j], z = wz[j];
        const float ox = fixed_is_wo ? k.fx : x, oy = fixed_is_wo ? k.fy : y,
                    oz = fixed_is_wo ? k.fz : z;
        const float ix = fixed_is_wo ? x : k.fx, iy = fixed_is_wo ? y : k.fy,
                    iz = fixed_is_wo ? z : k.fz;
        // Half vector, c and D(wm).
        const float hx = ox + ix, hy = oy + iy, hz = oz + iz;
        const float len2 = hx * hx + hy * hy + hz * hz;
        const float l = std::sqrt(len2);
        const float mx = hx / l, my = hy / l, mz = hz / l;
        float c = ox * mx + oy * my + oz * mz;
        const float cos2 = mz * mz;
        const float sx = mx / k.ax, sy = my / k.ay;
        const float t = (sx * sx + sy * sy) / cos2;
        const float d = formulas::blinn_d<FastMath>(k.log_norm, k.half_nu_p2, t, cos2);
        const bool valid = (oz > 0.f) & (iz > 0.f) & (len2 > 0.f) & (mz > 0.f) & (t < kInfinity);
        d_a[j] = valid ? d : 0.f;
        c = c < 0.f ? 0.f : (1.f < c ? 1.f : c);
        c_out[j] = valid ? c : 0.f;
        // Lambda of the free direction: exponent and table argument.
        const float lx = k.ax * x, ly = k.ay * y, lz = std::fabs(z);
        const float r = std::sqrt(lx * lx + ly * ly);
        const float mu = lz / r;
        e_a[j] = r == 0.f ? kInfinity : formulas::blinn_lambda_exponent<FastMath>(k.half_nu_m1, mu);
        mu_a[j] = mu;
        v_a[j] = formulas::blinn_lambda_v(k.s, lz, r);
    }
    for (std::size_t j = 0; j < n; ++j) rho_a[j] = formulas::blinn_rho(k.rho, v_a[j]);
    for (std::size_t j = 0; j < n; ++j) {
        const float e = e_a[j];
        float lam = formulas::blinn_lambda<FastMath>(k.k, e, mu_a[j], rho_a[j]);
        lam = e < k.zero_lambda_e ? lam : 0.f;  // also r = 0 (e = inf): mu = inf, Lambda = 0
        const float oz = fixed_is_wo ? k.fz : wz[j], iz = fixed_is_wo ? wz[j] : k.fz;
        const float lam_o = fixed_is_wo ? k.lam_fixed : lam,
                    lam_i = fixed_is_wo ? lam : k.lam_fixed;
        const float g = 1.f / (1.f + lam_o + lam_i);
        const float d = d_a[j];
        const float s = d * g / (4.f * oz) / iz;
        s_out[j] = d > 0.f ? s : 0.f;  // d = 0 on the discarded lanes (and where D underflows)
    }
}

FACET_TARGET_CLONES
void blinn_fixed_block(std::size_t n, const float* __restrict wx, const float* __restrict wy,
                       const float* __restrict wz, bool fixed_is_wo, BlinnConstants k,
                       float* __restrict s_out, float* __restrict c_out) {
    // The role of the fixed direction known at compile time in each loop (a run-time flag in
    // the loop kept GCC from vectorising it).
    if (fixed_is_wo)
        blinn_fixed_loop<true>(n, wx, wy, wz, k, s_out, c_out);
    else
        blinn_fixed_loop<false>(n, wx, wy, wz, k, s_out, c_out);
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
        apply_fresnel(m, s, c, {out.r + k0, out.g + k0, out.b + k0});
    }
}

void MicrofacetBatch::apply_fresnel(std::size_t n, const float* s, const float* c,
                                    RgbSoa out) const {
    if (m_fresnel_in_loop) {
        schlick_block(n, s, c, m_lobe.scale(), m_fa, m_fb, out.r, out.g, out.b);
    } else {
        // Dielectric / conductor Fresnel: scalar per element (exact, double inside).
        for (std::size_t j = 0; j < n; ++j) {
            Rgb v = m_lobe.scale() * m_lobe.fresnel().eval(c[j]) * s[j];
            out.r[j] = v.r, out.g[j] = v.g, out.b[j] = v.b;
        }
    }
}

void MicrofacetBatch::f_single_fixed(std::size_t n, const Vec3& fixed, bool fixed_is_wo, Vec3Soa w,
                                     RgbSoa out) const {
    if (m_smooth) {
        std::fill_n(out.r, n, 0.f), std::fill_n(out.g, n, 0.f), std::fill_n(out.b, n, 0.f);
        return;
    }
    const MicrofacetDistribution& d = m_lobe.distribution();
    float s[kBlock], c[kBlock], fx[kBlock], fy[kBlock], fz[kBlock];
    std::fill_n(fx, kBlock, fixed.x), std::fill_n(fy, kBlock, fixed.y);
    std::fill_n(fz, kBlock, fixed.z);
    const Vec3Soa f{fx, fy, fz};
    if (d.kind() == DistributionKind::GGX) {
        // f_single is the uncompensated f: the GGX kernel, compensated lobes included.
        const GgxConstants kc = ggx_constants(m_ax, m_ay, m_norm);
        for (std::size_t k0 = 0; k0 < n; k0 += kBlock) {
            const std::size_t m = std::min(kBlock, n - k0);
            const Vec3Soa v = offset(w, k0), o = fixed_is_wo ? f : v, i = fixed_is_wo ? v : f;
            ggx_f_block(m, o.x, o.y, o.z, i.x, i.y, i.z, kc, s, c);
            apply_fresnel(m, s, c, {out.r + k0, out.g + k0, out.b + k0});
        }
        return;
    }
    const float lam_fixed = d.lambda(fixed);
    if (d.kind() == DistributionKind::Blinn) {
        const BlinnConstants kc{d.m_ax,
                                d.m_ay,
                                d.m_log_norm,
                                float(0.5 * (d.m_nu + 2.0)),
                                d.m_blinn_half_nu_m1,
                                d.m_blinn_kf,
                                d.m_blinn_s,
                                MicrofacetDistribution::blinn_zero_lambda_exponent(),
                                d.m_blinn_rho->data(),
                                fixed.x,
                                fixed.y,
                                fixed.z,
                                lam_fixed};
        for (std::size_t k0 = 0; k0 < n; k0 += kBlock) {
            const std::size_t m = std::min(kBlock, n - k0);
            const Vec3Soa v = offset(w, k0);
            blinn_fixed_block(m, v.x, v.y, v.z, fixed_is_wo, kc, s, c);
            apply_fresnel(m, s, c, {out.r + k0, out.g + k0, out.b + k0});
        }
        return;
    }
    // Beckmann: MicrofacetReflection::evaluate per element, Lambda(fixed) once.
    for (std::size_t k = 0; k < n; ++k) {
        const Vec3 v = at(w, k), wo = fixed_is_wo ? fixed : v, wi = fixed_is_wo ? v : fixed;
        Rgb value(0.f);
        Vec3 wm;
        float cm, dm;
        if (wo.z > 0.f && wi.z > 0.f && m_lobe.half_vector_terms(wo, wi, wm, cm, dm)) {
            const float lam = d.lambda(v);
            value = m_lobe.single_from(cm, dm, fixed_is_wo ? lam_fixed : lam,
                                       fixed_is_wo ? lam : lam_fixed, wo.z, wi.z);
        }
        out.r[k] = value.r, out.g[k] = value.g, out.b[k] = value.b;
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
