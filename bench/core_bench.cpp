// Core micro-benchmarks (issue 2): ns per f, per pdf and per sample_f for each model, float,
// single thread, on pre-generated arrays of random directions and random numbers (no RNG cost
// inside the timed loop). Each benchmark walks an array of kN queries per iteration and reports
// the counter "s/call" = time / (iterations x kN), printed in ns ("16.2n").
//
// The peer (the yardstick, "a plain scalar GGX eval: D, separable G, Schlick F, RGB"):
// written inline below, once called per query through a non-inlined function (scalar), and once
// as a loop over structure-of-arrays inputs that the compiler auto-vectorises (batched). The
// full model (GGX, exact height-correlated Smith G, Schlick F, RGB scale) is compared with both.
//
// Run: facet_core_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only
#include <benchmark/benchmark.h>

#include <pcg_random.hpp>

#include <vector>

#include "facet/lambert.h"
#include "facet/microfacet.h"
#include "facet/microfacet_batch.h"
#include "facet/mirror.h"
#include "facet/registry.h"

namespace facet {
namespace {

constexpr int kN = 4096;

struct Queries {
    std::vector<Vec3> wo, wi;
    std::vector<float> uc;
    std::vector<Vec2> u;
};

// Random upper-hemisphere pairs (uniform), fixed seed.
const Queries& queries() {
    static const Queries q = [] {
        Queries r;
        pcg32 rng(12345);
        auto uf = [&] { return float(rng() >> 8) * 0x1p-24f; };
        for (int i = 0; i < kN; ++i) {
            r.wo.push_back(sample_uniform_hemisphere(Vec2(uf(), uf())));
            r.wi.push_back(sample_uniform_hemisphere(Vec2(uf(), uf())));
            r.uc.push_back(uf());
            r.u.push_back(Vec2(uf(), uf()));
        }
        return r;
    }();
    return q;
}

void set_ns_per_call(benchmark::State& state) {
    // kIsRate | kInvert: seconds per call (printed with an SI suffix, e.g. "16.2n").
    state.counters["s/call"] = benchmark::Counter(
        double(state.iterations()) * kN, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

template <class B>
void run_f(benchmark::State& state, const B& b) {
    const Queries& q = queries();
    for (auto _ : state) {
        for (int i = 0; i < kN; ++i) {
            Rgb r = b.f(q.wo[i], q.wi[i]);
            benchmark::DoNotOptimize(r);
        }
    }
    set_ns_per_call(state);
}
template <class B>
void run_pdf(benchmark::State& state, const B& b) {
    const Queries& q = queries();
    for (auto _ : state) {
        for (int i = 0; i < kN; ++i) {
            float p = b.pdf(q.wo[i], q.wi[i]);
            benchmark::DoNotOptimize(p);
        }
    }
    set_ns_per_call(state);
}
template <class B>
void run_sample(benchmark::State& state, const B& b) {
    const Queries& q = queries();
    for (auto _ : state) {
        for (int i = 0; i < kN; ++i) {
            auto s = b.sample_f(q.wo[i], q.uc[i], q.u[i]);
            benchmark::DoNotOptimize(s);
        }
    }
    set_ns_per_call(state);
}

// --- Models ----------------------------------------------------------------------------------

Material material(const char* model, std::vector<std::pair<std::string, ParamValue>> ps) {
    ParamSet p;
    for (auto& [k, v] : ps) p.set(k, v);
    return make_material(model, p);
}

const Rgb kF0(0.95f, 0.64f, 0.54f);  // copper-ish Schlick F0, same as the peer

MicrofacetReflection ggx_lobe(float ax, float ay, bool ec = false) {
    return MicrofacetReflection(MicrofacetDistribution::ggx(ax, ay), Fresnel::schlick(kF0),
                                Rgb(1.f), ec);
}

#define FACET_BENCH_MODEL(NAME, EXPR)              \
    void BM_f_##NAME(benchmark::State& s) {        \
        static const auto b = EXPR;                \
        run_f(s, b);                               \
    }                                              \
    void BM_pdf_##NAME(benchmark::State& s) {      \
        static const auto b = EXPR;                \
        run_pdf(s, b);                             \
    }                                              \
    void BM_sample_f_##NAME(benchmark::State& s) { \
        static const auto b = EXPR;                \
        run_sample(s, b);                          \
    }                                              \
    BENCHMARK(BM_f_##NAME);                        \
    BENCHMARK(BM_pdf_##NAME);                      \
    BENCHMARK(BM_sample_f_##NAME);

FACET_BENCH_MODEL(lambert, LambertReflection(Rgb(0.5f)))
FACET_BENCH_MODEL(mirror, MirrorReflection(Fresnel::schlick(kF0), Rgb(1.f)))
FACET_BENCH_MODEL(ggx, ggx_lobe(0.3f, 0.3f))
FACET_BENCH_MODEL(ggx_aniso, ggx_lobe(0.1f, 0.5f))
FACET_BENCH_MODEL(ggx_energy_comp, ggx_lobe(0.3f, 0.3f, true))
FACET_BENCH_MODEL(beckmann, MicrofacetReflection(MicrofacetDistribution::beckmann(0.3f, 0.3f),
                                                 Fresnel::schlick(kF0), Rgb(1.f), false))
FACET_BENCH_MODEL(blinn, MicrofacetReflection(MicrofacetDistribution::blinn(20.f, 20.f),
                                              Fresnel::schlick(kF0), Rgb(1.f), false))
FACET_BENCH_MODEL(ggx_conductor, MicrofacetReflection(MicrofacetDistribution::ggx(0.3f, 0.3f),
                                                      Fresnel::conductor(Rgb(0.2f, 0.9f, 1.1f),
                                                                         Rgb(3.9f, 2.4f, 2.2f)),
                                                      Rgb(1.f), false))
FACET_BENCH_MODEL(material_ggx,
                  material("ggx", {{"alpha", 0.3}, {"fresnel", std::string("schlick")}}))
FACET_BENCH_MODEL(material_composite, material("composite", {{"alpha", 0.3},
                                                             {"mirror_reflectance", 0.2},
                                                             {"glossy_reflectance", 0.8}}))

// --- The peer: plain GGX with separable Smith G and Schlick F --------------------------------

// D_GGX (Walter 2007 eq. 33), separable Smith G1(wo) G1(wi) (eq. 34), Schlick F, RGB.
inline Rgb peer_ggx_inline(const Vec3& wo, const Vec3& wi, float alpha, const Rgb& f0) {
    if (wo.z <= 0.f || wi.z <= 0.f) return Rgb(0.f);
    Vec3 h = glm::normalize(wo + wi);
    float a2 = alpha * alpha;
    float c2 = h.z * h.z;
    float d = c2 * (a2 - 1.f) + 1.f;
    float D = a2 / (kPi * d * d);
    auto g1 = [a2](float c) { return 2.f * c / (c + std::sqrt(a2 + (1.f - a2) * c * c)); };
    float G = g1(wo.z) * g1(wi.z);
    float m = 1.f - glm::dot(wo, h);
    float m5 = m * m * m * m * m;
    Rgb F = f0 + (Rgb(1.f) - f0) * m5;
    return F * (D * G / (4.f * wo.z * wi.z));
}

__attribute__((noinline)) Rgb peer_ggx_scalar(const Vec3& wo, const Vec3& wi, float alpha,
                                              const Rgb& f0) {
    return peer_ggx_inline(wo, wi, alpha, f0);
}

void BM_f_peer_ggx_scalar(benchmark::State& state) {
    const Queries& q = queries();
    for (auto _ : state) {
        for (int i = 0; i < kN; ++i) {
            Rgb r = peer_ggx_scalar(q.wo[i], q.wi[i], 0.3f, kF0);
            benchmark::DoNotOptimize(r);
        }
    }
    set_ns_per_call(state);
}
BENCHMARK(BM_f_peer_ggx_scalar);

// Batched: structure-of-arrays inputs and outputs, a straight loop the compiler vectorises.
struct Soa {
    std::vector<float> ox, oy, oz, ix, iy, iz, r, g, b;
};
const Soa& soa() {
    static Soa s = [] {
        Soa r;
        const Queries& q = queries();
        for (int i = 0; i < kN; ++i) {
            r.ox.push_back(q.wo[i].x), r.oy.push_back(q.wo[i].y), r.oz.push_back(q.wo[i].z);
            r.ix.push_back(q.wi[i].x), r.iy.push_back(q.wi[i].y), r.iz.push_back(q.wi[i].z);
        }
        r.r.resize(kN), r.g.resize(kN), r.b.resize(kN);
        return r;
    }();
    return s;
}

// The loop body, shared by the baseline-ISA and the AVX2-cloned peer.
__attribute__((always_inline)) inline void peer_ggx_loop(
    const float* __restrict ox, const float* __restrict oy, const float* __restrict oz,
    const float* __restrict ix, const float* __restrict iy, const float* __restrict iz, float alpha,
    const Rgb& f0, float* __restrict r, float* __restrict g, float* __restrict b, int n) {
    const float a2 = alpha * alpha, f0r = f0.r, f0g = f0.g, f0b = f0.b;
    for (int i = 0; i < n; ++i) {
        float hx = ox[i] + ix[i], hy = oy[i] + iy[i], hz = oz[i] + iz[i];
        float inv = 1.f / std::sqrt(hx * hx + hy * hy + hz * hz);
        hx *= inv, hy *= inv, hz *= inv;
        float d = hz * hz * (a2 - 1.f) + 1.f;
        float D = a2 / (kPi * d * d);
        float co = oz[i], ci = iz[i];
        float g1o = 2.f * co / (co + std::sqrt(a2 + (1.f - a2) * co * co));
        float g1i = 2.f * ci / (ci + std::sqrt(a2 + (1.f - a2) * ci * ci));
        float m = 1.f - (ox[i] * hx + oy[i] * hy + oz[i] * hz);
        float m5 = m * m * m * m * m;
        // The pre-generated directions are all above the surface: no below-horizon test here.
        float k = D * g1o * g1i / (4.f * co * ci);
        r[i] = (f0r + (1.f - f0r) * m5) * k;
        g[i] = (f0g + (1.f - f0g) * m5) * k;
        b[i] = (f0b + (1.f - f0b) * m5) * k;
    }
}

#define FACET_PEER_ARGS                                                                            \
    const float *__restrict ox, const float *__restrict oy, const float *__restrict oz,            \
        const float *__restrict ix, const float *__restrict iy, const float *__restrict iz,        \
        float alpha, const Rgb &f0, float *__restrict r, float *__restrict g, float *__restrict b, \
        int n

void peer_ggx_batch(FACET_PEER_ARGS) {
    peer_ggx_loop(ox, oy, oz, ix, iy, iz, alpha, f0, r, g, b, n);
}

// The same peer loop compiled for AVX2 too (the loader picks the AVX2 copy where the CPU has
// it), because Facet's own batched kernel is built that way: like for like.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
void peer_ggx_batch_avx2(FACET_PEER_ARGS) {
    peer_ggx_loop(ox, oy, oz, ix, iy, iz, alpha, f0, r, g, b, n);
}

template <auto Kernel>
void run_peer_batched(benchmark::State& state) {
    Soa& s = const_cast<Soa&>(soa());
    for (auto _ : state) {
        Kernel(s.ox.data(), s.oy.data(), s.oz.data(), s.ix.data(), s.iy.data(), s.iz.data(), 0.3f,
               kF0, s.r.data(), s.g.data(), s.b.data(), kN);
        benchmark::DoNotOptimize(s.r.data());
        benchmark::ClobberMemory();
    }
    set_ns_per_call(state);
}
void BM_f_peer_ggx_batched(benchmark::State& state) {
    run_peer_batched<peer_ggx_batch>(state);
}
BENCHMARK(BM_f_peer_ggx_batched);
void BM_f_peer_ggx_batched_avx2(benchmark::State& state) {
    run_peer_batched<peer_ggx_batch_avx2>(state);
}
BENCHMARK(BM_f_peer_ggx_batched_avx2);

// Facet's batched API (facet/microfacet_batch.h): the full model (exact height-correlated
// Smith G, Schlick F, RGB scale), vectorised, on the same SoA queries.
void BM_f_ggx_batched(benchmark::State& state) {
    static const MicrofacetBatch batch(ggx_lobe(0.3f, 0.3f));
    Soa& s = const_cast<Soa&>(soa());
    for (auto _ : state) {
        batch.f(kN, {s.ox.data(), s.oy.data(), s.oz.data()},
                {s.ix.data(), s.iy.data(), s.iz.data()}, {s.r.data(), s.g.data(), s.b.data()});
        benchmark::DoNotOptimize(s.r.data());
        benchmark::ClobberMemory();
    }
    set_ns_per_call(state);
}
BENCHMARK(BM_f_ggx_batched);
void BM_pdf_ggx_batched(benchmark::State& state) {
    static const MicrofacetBatch batch(ggx_lobe(0.3f, 0.3f));
    Soa& s = const_cast<Soa&>(soa());
    for (auto _ : state) {
        batch.pdf(kN, {s.ox.data(), s.oy.data(), s.oz.data()},
                  {s.ix.data(), s.iy.data(), s.iz.data()}, s.r.data());
        benchmark::DoNotOptimize(s.r.data());
        benchmark::ClobberMemory();
    }
    set_ns_per_call(state);
}
BENCHMARK(BM_pdf_ggx_batched);

// The full model in a batch loop over the same queries (scalar inside: f() is out of line),
// for a like-for-like comparison with the batched peer.
void BM_f_ggx_batch_loop(benchmark::State& state) {
    static const auto lobe = ggx_lobe(0.3f, 0.3f);
    const Queries& q = queries();
    std::vector<Rgb> out(kN);
    for (auto _ : state) {
        for (int i = 0; i < kN; ++i) out[i] = lobe.f(q.wo[i], q.wi[i]);
        benchmark::DoNotOptimize(out.data());
        benchmark::ClobberMemory();
    }
    set_ns_per_call(state);
}
BENCHMARK(BM_f_ggx_batch_loop);

}  // namespace
}  // namespace facet

BENCHMARK_MAIN();
