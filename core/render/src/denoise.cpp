// Feature-guided non-local means on two half-buffers (conventions in denoise.h).
#include "facet/render/denoise.h"

#include "facet/render/aov.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <xmmintrin.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace facet::render {

namespace {

// Below this albedo a channel is not divided out (black surfaces, the background).
constexpr float kMinAlbedo = 1e-3f;
// Keeps d finite where both variances are 0 (a noise-free input): any colour difference then
// gives a weight of 0, so such an image passes through.
constexpr float kEpsilon = 1e-10f;
// Filter strengths k (Rousselle et al. 2012 use 0.45; the stronger one serves flat regions).
constexpr std::array<float, 2> kStrengths{0.45f, 1.0f};
constexpr int kCandidates = int(kStrengths.size());
// Feature bandwidths: albedo and normal absolute (unit normals differ by 0.2 at 11.5 degrees);
// inverse depth relative to the pixel's own, after its first-order prediction (see prepare).
constexpr float kAlbedoBandwidth = 0.1f, kNormalBandwidth = 0.2f, kDepthBandwidth = 0.02f;
// Ridge on the first-order fit's slopes, relative to the weight sum (a pixel's squared
// offset; see filter_band).
constexpr double kRidge = 0.05;
// Radius of the box over which the candidates' error estimates are averaged.
constexpr int kErrorRadius = 3;
// Rows per band (the unit of parallel work and of scratch memory).
constexpr int kBandRows = 16;

// exp(x) for x <= 0 (x below -80 gives exp(-80) ~ 1.8e-35): 2^t as 2^floor(t) times a degree-5
// polynomial of 2^f on [0, 1) (relative error below 1e-6), branch-free so that loops over it
// vectorise. Weights need no more accuracy, and libm's expf would not vectorise here.
inline float exp_neg(float x) {
    x = x > -80.f ? x : -80.f;
    const float t = x * 1.44269504f + 128.f;  // in [12.5, 128]: int() is floor()
    const int i = int(t);
    const float f = t - float(i);
    const float p =
        1.f + f * (0.69314718f +
                   f * (0.24022652f + f * (0.05550411f + f * (0.00961813f + f * 0.00133336f))));
    // 2^(i - 128), exponent field i - 1
    return p * std::bit_cast<float>(static_cast<std::uint32_t>(i - 1) << 23);
}

// Flush-to-zero and denormals-are-zero on this thread while alive (the render threads run so,
// for Embree): the denoiser's bits then do not depend on the floating-point mode of the process
// or thread that calls it (a value below 1.2e-38 would otherwise round differently).
class FlushDenormals {
  public:
    FlushDenormals() : m_saved(_mm_getcsr()) { _mm_setcsr(m_saved | 0x8040u); }
    ~FlushDenormals() { _mm_setcsr(m_saved); }
    FlushDenormals(const FlushDenormals&) = delete;
    FlushDenormals& operator=(const FlushDenormals&) = delete;

  private:
    unsigned m_saved;
};

// Planar float images: plane k is data[k * n, (k + 1) * n).
struct Planes {
    std::size_t n = 0;
    std::vector<float> data;
    Planes(std::size_t pixels, int count) : n(pixels), data(pixels * std::size_t(count), 0.f) {}
    float* operator[](int k) { return data.data() + std::size_t(k) * n; }
    const float* operator[](int k) const { return data.data() + std::size_t(k) * n; }
};

// out = the mean of in over the (2r + 1)^2 box around each pixel, clipped to the image.
void box_mean(const float* in, float* out, int w, int h, int r) {
    std::vector<float> rows(std::size_t(w) * h);
    for (int y = 0; y < h; ++y) {
        const float* src = in + std::size_t(y) * w;
        float* dst = rows.data() + std::size_t(y) * w;
        for (int x = 0; x < w; ++x) {
            const int x0 = std::max(0, x - r), x1 = std::min(w - 1, x + r);
            float s = 0.f;
            for (int k = x0; k <= x1; ++k) s += src[k];
            dst[x] = s / float(x1 - x0 + 1);
        }
    }
    for (int y = 0; y < h; ++y) {
        const int y0 = std::max(0, y - r), y1 = std::min(h - 1, y + r);
        float* dst = out + std::size_t(y) * w;
        for (int x = 0; x < w; ++x) dst[x] = 0.f;
        for (int k = y0; k <= y1; ++k) {
            const float* src = rows.data() + std::size_t(k) * w;
            for (int x = 0; x < w; ++x) dst[x] += src[x];
        }
        const float inv = 1.f / float(y1 - y0 + 1);
        for (int x = 0; x < w; ++x) dst[x] *= inv;
    }
}

void check_input(const Image* img, const char* name, const Image& ref) {
    if (img == nullptr || img->width() == 0 || img->height() == 0)
        throw std::invalid_argument(std::string("denoise: ") + name + ": missing (empty image)");
    if (img->width() != ref.width() || img->height() != ref.height())
        throw std::invalid_argument(
            std::string("denoise: ") + name + ": " + std::to_string(img->width()) + " x " +
            std::to_string(img->height()) + " pixels, but half_a is " +
            std::to_string(ref.width()) + " x " + std::to_string(ref.height()));
    for (int y = 0; y < img->height(); ++y)
        for (int x = 0; x < img->width(); ++x) {
            const Rgb& c = img->at(x, y);
            if (!is_finite(c))
                throw std::invalid_argument(std::string("denoise: ") + name + ": pixel (" +
                                            std::to_string(x) + ", " + std::to_string(y) +
                                            ") is not finite");
        }
}

// The inputs in planar form (see denoise.h for the symbols).
struct Prepared {
    int w, h;
    Planes half;  // 0..2: X_a / m, 3..5: X_b / m
    Planes var;   // 0: V
    // 0..2 albedo / s_a, 3..5 normal / s_n, 6 inverse depth u, 7 1 / (s_z u)^2, 8..9 du/dx,
    // du/dy
    Planes feat;
    Planes mod;  // 0..2 the albedo divided out (1 where below kMinAlbedo)
    Prepared(int w_, int h_)
        : w(w_),
          h(h_),
          half(std::size_t(w_) * h_, 6),
          var(std::size_t(w_) * h_, 1),
          feat(std::size_t(w_) * h_, 10),
          mod(std::size_t(w_) * h_, 3) {}
};

void prepare(const DenoiseInput& in, Prepared& p) {
    const int w = p.w, h = p.h;
    std::vector<float> raw_var(std::size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            const Rgb a = in.albedo->at(x, y), n = in.normal->at(x, y);
            const Rgb xa = in.half_a->at(x, y), xb = in.half_b->at(x, y);
            float v = 0.f;
            for (int c = 0; c < 3; ++c) {
                const float m = a[c] > kMinAlbedo ? a[c] : 1.f;
                p.mod[c][i] = m;
                p.half[c][i] = xa[c] / m;
                p.half[3 + c][i] = xb[c] / m;
                const float d = (xa[c] - xb[c]) / m;
                v += 0.5f * d * d;
                p.feat[c][i] = a[c] / kAlbedoBandwidth;
                p.feat[3 + c][i] = n[c] / kNormalBandwidth;
            }
            raw_var[i] = v / 3.f;
            // Inverse depth u = 1 / z (0 where nothing is hit): affine in screen position over
            // a plane seen by a perspective camera, so a plane predicts its neighbours exactly.
            const float z = in.depth->at(x, y).r;
            const float u = z > 0.f && z < 0.5f * kMissDepth ? 1.f / z : 0.f;
            p.feat[6][i] = u;
            const float s = kDepthBandwidth * std::max(u, 1e-12f);
            p.feat[7][i] = 1.f / (s * s);
        }
    box_mean(raw_var.data(), p.var[0], w, h, 1);
    // du/dx and du/dy: of the two one-sided differences the smaller (a surface's own slope,
    // not the jump to the surface behind an edge).
    const float* u = p.feat[6];
    auto slope = [](float back, float fwd) {
        return std::fabs(back) < std::fabs(fwd) ? back : fwd;
    };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            const float r = x + 1 < w ? u[i + 1] - u[i] : 0.f;
            const float l = x > 0 ? u[i] - u[i - 1] : r;
            const float b = y + 1 < h ? u[i + w] - u[i] : 0.f;
            const float t = y > 0 ? u[i] - u[i - w] : b;
            p.feat[8][i] = slope(l, x + 1 < w ? r : l);
            p.feat[9][i] = slope(t, y + 1 < h ? b : t);
        }
}

// The filtered halves F_k of one band of rows [y0, y1) into out (planes (half * kCandidates +
// k) * 3 + c).
void filter_band(const Prepared& p, int radius, int y0, int y1, Planes& out) {
    const int w = p.w, h = p.h;
    const int m0 = std::max(0, y0 - 1), m1 = std::min(h, y1 + 1);
    const int mrows = m1 - m0, rows = y1 - y0;
    const std::size_t ms = std::size_t(mrows) * w, bs = std::size_t(rows) * w;
    // d for each half over the margin rows, then its horizontal and vertical 3-box.
    std::vector<float> d(2 * ms), dh(2 * ms), dp(2 * bs);
    // Accumulators of the weighted first-order fit, per slot (2 halves x kCandidates): the
    // weight moments sum w (1, dx, dy, dx^2, dy^2, dx dy) and the value moments sum w X_c
    // (1, dx, dy) per channel.
    constexpr int kMoments = 6 + 9;
    std::vector<float> acc(std::size_t(2 * kCandidates * kMoments) * bs, 0.f);
    std::vector<float> wf_row(static_cast<std::size_t>(w), 0.f);
    float inv_k2[kCandidates];
    for (int k = 0; k < kCandidates; ++k) inv_k2[k] = 1.f / (kStrengths[k] * kStrengths[k]);
    const float* V = p.var[0];

    for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx) {
            // d(p, p + (dx, dy)) with the neighbour clamped into the image (the patch's
            // border), per half.
            for (int y = m0; y < m1; ++y) {
                const int qy = std::clamp(y + dy, 0, h - 1);
                for (int hh = 0; hh < 2; ++hh) {
                    const float* X0 = p.half[3 * hh] + std::size_t(y) * w;
                    const float* X1 = p.half[3 * hh + 1] + std::size_t(y) * w;
                    const float* X2 = p.half[3 * hh + 2] + std::size_t(y) * w;
                    const float* Q0 = p.half[3 * hh] + std::size_t(qy) * w;
                    const float* Q1 = p.half[3 * hh + 1] + std::size_t(qy) * w;
                    const float* Q2 = p.half[3 * hh + 2] + std::size_t(qy) * w;
                    const float* Vp = V + std::size_t(y) * w;
                    const float* Vq = V + std::size_t(qy) * w;
                    float* D = d.data() + hh * ms + std::size_t(y - m0) * w;
                    for (int x = 0; x < w; ++x) {
                        const int qx = std::clamp(x + dx, 0, w - 1);
                        const float a = X0[x] - Q0[qx], b = X1[x] - Q1[qx], c = X2[x] - Q2[qx];
                        const float vp = Vp[x], vq = Vq[qx];
                        D[x] = ((a * a + b * b + c * c) * (1.f / 3.f) - (vp + std::min(vp, vq))) /
                               (kEpsilon + vp + std::min(vp, vq));
                    }
                }
            }
            for (int hh = 0; hh < 2; ++hh) {
                for (int y = 0; y < mrows; ++y) {
                    const float* D = d.data() + hh * ms + std::size_t(y) * w;
                    float* H = dh.data() + hh * ms + std::size_t(y) * w;
                    if (w == 1) {
                        H[0] = D[0];
                        continue;
                    }
                    H[0] = 0.5f * (D[0] + D[1]);
                    for (int x = 1; x + 1 < w; ++x)
                        H[x] = (D[x - 1] + D[x] + D[x + 1]) * (1.f / 3.f);
                    H[w - 1] = 0.5f * (D[w - 2] + D[w - 1]);
                }
                for (int y = y0; y < y1; ++y) {
                    const int a = std::max(y - 1, m0), b = std::min(y + 1, m1 - 1);
                    float* P = dp.data() + hh * bs + std::size_t(y - y0) * w;
                    const float inv = 1.f / float(b - a + 1);
                    for (int x = 0; x < w; ++x) P[x] = 0.f;
                    for (int r = a; r <= b; ++r) {
                        const float* H = dh.data() + hh * ms + std::size_t(r - m0) * w;
                        for (int x = 0; x < w; ++x) P[x] += H[x];
                    }
                    for (int x = 0; x < w; ++x) P[x] *= inv;
                }
            }
            // Weights and sums for the pixels whose neighbour lies inside the image.
            const float fdx = float(dx), fdy = float(dy);
            const int x_lo = std::max(0, -dx), x_hi = std::min(w, w - dx);
            for (int y = y0; y < y1; ++y) {
                const int qy = y + dy;
                if (qy < 0 || qy >= h) continue;
                const std::size_t row = std::size_t(y) * w, qrow = std::size_t(qy) * w + dx;
                const std::size_t brow = std::size_t(y - y0) * w;
                const float* F[10];
                const float* G[7];
                for (int f = 0; f < 10; ++f) F[f] = p.feat[f] + row;
                for (int f = 0; f < 7; ++f) G[f] = p.feat[f] + qrow;
                float* WF = wf_row.data();
#pragma GCC ivdep
                for (int x = x_lo; x < x_hi; ++x) {
                    float f = 0.f;
                    for (int c = 0; c < 6; ++c) {
                        const float e = F[c][x] - G[c][x];
                        f += e * e;
                    }
                    const float ez = G[6][x] - F[6][x] - F[8][x] * fdx - F[9][x] * fdy;
                    f += ez * ez * F[7][x];
                    WF[x] = exp_neg(-f);
                }
                for (int hh = 0; hh < 2; ++hh) {
                    const float* P = dp.data() + hh * bs + brow;
                    const float* Q0 = p.half[3 * hh] + qrow;
                    const float* Q1 = p.half[3 * hh + 1] + qrow;
                    const float* Q2 = p.half[3 * hh + 2] + qrow;
                    for (int k = 0; k < kCandidates; ++k) {
                        float* A =
                            acc.data() + std::size_t((hh * kCandidates + k) * kMoments) * bs + brow;
                        float* M[kMoments];
                        for (int m = 0; m < kMoments; ++m) M[m] = A + std::size_t(m) * bs;
                        const float ik = inv_k2[k];
#pragma GCC ivdep
                        for (int x = x_lo; x < x_hi; ++x) {
                            const float d = P[x] > 0.f ? P[x] : 0.f;
                            const float wc = exp_neg(-d * ik);
                            const float wt = wc < WF[x] ? wc : WF[x];
                            const float wx = wt * fdx, wy = wt * fdy;
                            M[0][x] += wt;
                            M[1][x] += wx;
                            M[2][x] += wy;
                            M[3][x] += wx * fdx;
                            M[4][x] += wy * fdy;
                            M[5][x] += wx * fdy;
                            const float q0 = Q0[x], q1 = Q1[x], q2 = Q2[x];
                            M[6][x] += wt * q0;
                            M[7][x] += wx * q0;
                            M[8][x] += wy * q0;
                            M[9][x] += wt * q1;
                            M[10][x] += wx * q1;
                            M[11][x] += wy * q1;
                            M[12][x] += wt * q2;
                            M[13][x] += wx * q2;
                            M[14][x] += wy * q2;
                        }
                    }
                }
            }
        }
    // The fit's value at the pixel: the constant of the weighted least-squares plane
    // c + a dx + b dy through the neighbours (first-order regression in screen space, which
    // follows a gradient of the lighting without the bias a weighted mean has where the
    // weights are lopsided). The slopes get a small ridge (kRidge times the weight sum) so that
    // a neighbourhood on a line stays solvable; the centre's own weight is 1 (f = 0, d <= 0),
    // so the weight sum is at least 1.
    for (int slot = 0; slot < 2 * kCandidates; ++slot) {
        const float* A = acc.data() + std::size_t(slot * kMoments) * bs;
        for (int y = y0; y < y1; ++y)
            for (int x = 0; x < w; ++x) {
                const std::size_t b = std::size_t(y - y0) * w + x, i = std::size_t(y) * w + x;
                auto m = [&](int k) { return double(A[std::size_t(k) * bs + b]); };
                const double s0 = m(0), sx = m(1), sy = m(2);
                const double sxx = m(3) + kRidge * s0, syy = m(4) + kRidge * s0, sxy = m(5);
                // First row of the inverse of [[s0 sx sy] [sx sxx sxy] [sy sxy syy]].
                const double c0 = sxx * syy - sxy * sxy, c1 = sy * sxy - sx * syy,
                             c2 = sx * sxy - sy * sxx;
                const double det = s0 * c0 + sx * c1 + sy * c2;
                for (int c = 0; c < 3; ++c) {
                    const double v0 = m(6 + 3 * c), vx = m(7 + 3 * c), vy = m(8 + 3 * c);
                    const double fit = det > 1e-9 * s0 * c0 && c0 > 0.0
                                           ? (c0 * v0 + c1 * vx + c2 * vy) / det
                                           : v0 / s0;
                    out[3 * slot + c][i] = float(fit);
                }
            }
    }
}

template <class F>
void run_parallel(int threads, int count, const F& body) {
    auto work = [&] {
        tbb::parallel_for(tbb::blocked_range<int>(0, count, 1),
                          [&](const tbb::blocked_range<int>& r) {
                              const FlushDenormals ftz;
                              for (int i = r.begin(); i < r.end(); ++i) body(i);
                          });
    };
    if (threads > 0) {
        tbb::task_arena arena(threads);
        arena.execute(work);
    } else {
        work();
    }
}

}  // namespace

Image denoise(const DenoiseInput& in, const DenoiseOptions& o) {
    if (in.half_a == nullptr || in.half_a->width() == 0 || in.half_a->height() == 0)
        throw std::invalid_argument("denoise: half_a: missing (empty image)");
    const Image& ref = *in.half_a;
    check_input(in.half_a, "half_a", ref);
    check_input(in.half_b, "half_b", ref);
    check_input(in.albedo, "albedo", ref);
    check_input(in.normal, "normal", ref);
    check_input(in.depth, "depth", ref);
    if (o.radius < 1 || o.radius > 20)
        throw std::invalid_argument("denoise: radius: expected 1..20, got " +
                                    std::to_string(o.radius));
    if (o.threads < 0)
        throw std::invalid_argument("denoise: threads: expected >= 0, got " +
                                    std::to_string(o.threads));
    const int w = ref.width(), h = ref.height();
    const std::size_t n = std::size_t(w) * h;
    const FlushDenormals ftz;
    Prepared p(w, h);
    prepare(in, p);

    Planes filtered(n, 2 * kCandidates * 3);
    const int bands = (h + kBandRows - 1) / kBandRows;
    run_parallel(o.threads, bands, [&](int b) {
        filter_band(p, o.radius, b * kBandRows, std::min(h, (b + 1) * kBandRows), filtered);
    });

    // Error estimates E_k per half against the other half, averaged over a box.
    Planes err(n, 2 * kCandidates), err_box(n, 2 * kCandidates);
    for (int hh = 0; hh < 2; ++hh)
        for (int k = 0; k < kCandidates; ++k) {
            const int slot = hh * kCandidates + k;
            float* E = err[slot];
            for (std::size_t i = 0; i < n; ++i) {
                float e = 0.f;
                for (int c = 0; c < 3; ++c) {
                    const float r = filtered[3 * slot + c][i] - p.half[3 * (1 - hh) + c][i];
                    e += r * r;
                }
                E[i] = e;
            }
        }
    run_parallel(o.threads, 2 * kCandidates,
                 [&](int slot) { box_mean(err[slot], err_box[slot], w, h, kErrorRadius); });

    Image out(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            Rgb sum(0.f);
            for (int hh = 0; hh < 2; ++hh) {
                int best = 0;
                for (int k = 1; k < kCandidates; ++k)
                    if (err_box[hh * kCandidates + k][i] < err_box[hh * kCandidates + best][i])
                        best = k;
                const int slot = hh * kCandidates + best;
                for (int c = 0; c < 3; ++c) sum[c] += filtered[3 * slot + c][i];
            }
            for (int c = 0; c < 3; ++c) out.at(x, y)[c] = 0.5f * sum[c] * p.mod[c][i];
        }
    return out;
}

DenoisedRender render_denoised(const Scene& scene, const RenderOptions& options,
                               const DenoiseOptions& denoise_options) {
    if (options.region.has_value() || options.sample_begin != 0 || options.sample_end != 0)
        throw std::invalid_argument(
            "denoise: renders the whole image and every sample (no region or sample range): a "
            "denoiser is not split-invariant, so denoise the merged halves");
    if (resolve_settings(scene, options).adaptive_threshold > 0.0)
        throw std::invalid_argument(
            "denoise: cannot be combined with adaptive sampling (adaptive_threshold): the two "
            "half-buffers are sample ranges, which an adaptive render does not split into");
    const ResolvedSettings rs = resolve_settings(scene, options);
    if (rs.time_budget_s > 0.0)
        throw std::invalid_argument(
            "denoise: needs a fixed spp, not a time budget: the two half-buffers must hold the "
            "same number of samples");
    if (rs.spp < 2)
        throw std::invalid_argument("denoise: needs at least 2 samples per pixel, got " +
                                    std::to_string(rs.spp));
    DenoisedRender out;
    std::vector<RenderPart> halves;
    for (const auto& [begin, end] : {std::pair{0, rs.spp / 2}, std::pair{rs.spp / 2, rs.spp}}) {
        RenderOptions h = options;
        h.spp = rs.spp;
        h.sample_begin = begin;
        h.sample_end = end;
        RenderSession session(scene, h);
        session.render();
        halves.push_back(session.part());
        const RenderStats& st = session.stats();
        out.stats.kernel = st.kernel;
        out.stats.seconds += st.seconds;
        out.stats.passes += st.passes;
        out.stats.threads = st.threads;
        out.stats.paths += st.paths;
        out.stats.rays += st.rays;
        out.stats.shadow_rays += st.shadow_rays;
        out.stats.nonfinite += st.nonfinite;
        out.stats.cancelled = out.stats.cancelled || st.cancelled;
    }
    out.stats.spp = rs.spp;
    const Image a = halves[0].film.resolve(), b = halves[1].film.resolve();
    out.raw = merge_parts(halves, {"first half", "second half"}).resolve();
    DenoiseOptions d = denoise_options;
    d.threads = rs.threads;
    DenoisedHalves dh = denoise_halves(scene, a, b, rs.spp, rs.seed, d);
    out.image = std::move(dh.image);
    out.features = std::move(dh.features);
    return out;
}

DenoisedHalves denoise_halves(const Scene& scene, const Image& half_a, const Image& half_b, int spp,
                              std::uint64_t seed, const DenoiseOptions& options) {
    DenoisedHalves out;
    AovOptions ao;
    ao.which = kAovAlbedo | kAovNormal | kAovDepth;
    ao.spp = spp;
    ao.seed = seed;
    ao.threads = options.threads;
    out.features = render_aovs(scene, ao);
    out.image =
        denoise({&half_a, &half_b, &out.features.albedo, &out.features.normal, &out.features.depth},
                options);
    return out;
}

}  // namespace facet::render
