// Feature-guided non-local means on two half-buffers (conventions in denoise.h).
#include "facet/render/denoise.h"

#include "facet/render/aov.h"
#include "facet/target_clones.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <xmmintrin.h>

#ifdef __linux__
#include <sys/mman.h>
#endif

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

namespace facet::render {

namespace {

// Below this albedo a channel is not divided out (black surfaces, the background).
constexpr float kMinAlbedo = 1e-3f;
// Nor, given the feature variances, where the pixel's normal or depth varies among its samples
// (normal_variance or depth_variance above 0: an edge, depth of field, a curved, bumped or
// slanted surface): the output is multiplied back by the albedo, so a noisy albedo's noise
// would pass into the image unfiltered, and the variance-cancelled albedo weight keeps texture
// edges there. A pixel of one flat surface (both variances 0) is divided out, so zero
// variances give the image of none. The albedo's own variance is not the test: it is high on
// texture edges and glossy or glass albedos of one surface, where not dividing cost (16-spp
// denoised MSE, variances against none: suzanne_glass 1.29, showcase 1.05; this rule 0.88, 0.99).
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
// Rows and columns per tile (the unit of parallel work and of scratch memory: about
// 4 kMoments kCandidates floats per pixel of a tile).
constexpr int kBandRows = 16, kTileCols = 64;
// Zero columns on each side of the padded half planes (Prepared): the largest radius plus the
// lanes a tile's last vector reads past the image.
constexpr int kPad = 20 + 8;

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
// A zero-filled float array for the image-sized planes. On Linux it is mapped anonymously and
// advised as transparent huge pages: a frame's planes take a few hundred MB, and their first
// touch then faults once per 2 MiB instead of once per 4 KiB page.
class ZeroBuffer {
  public:
    explicit ZeroBuffer(std::size_t count) : m_bytes(std::max<std::size_t>(count, 1) * 4) {
#ifdef __linux__
        void* p =
            mmap(nullptr, m_bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (p == MAP_FAILED) throw std::bad_alloc();
        madvise(p, m_bytes, MADV_HUGEPAGE);  // advice only: a refusal changes nothing
        m_data = static_cast<float*>(p);
#else
        m_data = new float[m_bytes / 4]();
#endif
    }
    ~ZeroBuffer() {
#ifdef __linux__
        munmap(m_data, m_bytes);
#else
        delete[] m_data;
#endif
    }
    ZeroBuffer(const ZeroBuffer&) = delete;
    ZeroBuffer& operator=(const ZeroBuffer&) = delete;
    float* data() {
        return m_data;
    }
    const float* data() const {
        return m_data;
    }

  private:
    std::size_t m_bytes;
    float* m_data = nullptr;
};

struct Planes {
    std::size_t n = 0;
    ZeroBuffer data;
    Planes(std::size_t pixels, int count) : n(pixels), data(pixels * std::size_t(count)) {}
    float* operator[](int k) { return data.data() + std::size_t(k) * n; }
    const float* operator[](int k) const { return data.data() + std::size_t(k) * n; }
};

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

// out = the mean of in over the (2r + 1)^2 box around each pixel, clipped to the image (out
// may be in).
void box_mean(const float* in, float* out, int w, int h, int r) {
    ZeroBuffer rows(std::size_t(w) * h);
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

// A variance (nonnegative = true) must also be >= 0.
void check_input(const Image* img, const char* name, const Image& ref, const char* ref_name,
                 bool nonnegative = false) {
    if (img == nullptr || img->width() == 0 || img->height() == 0)
        throw std::invalid_argument(std::string("denoise: ") + name + ": missing (empty image)");
    if (img->width() != ref.width() || img->height() != ref.height())
        throw std::invalid_argument(
            std::string("denoise: ") + name + ": " + std::to_string(img->width()) + " x " +
            std::to_string(img->height()) + " pixels, but " + ref_name + " is " +
            std::to_string(ref.width()) + " x " + std::to_string(ref.height()));
    for (int y = 0; y < img->height(); ++y)
        for (int x = 0; x < img->width(); ++x) {
            const Rgb& c = img->at(x, y);
            if (!is_finite(c))
                throw std::invalid_argument(std::string("denoise: ") + name + ": pixel (" +
                                            std::to_string(x) + ", " + std::to_string(y) +
                                            ") is not finite");
            if (nonnegative && (c.r < 0.f || c.g < 0.f || c.b < 0.f))
                throw std::invalid_argument(std::string("denoise: ") + name + ": pixel (" +
                                            std::to_string(x) + ", " + std::to_string(y) +
                                            ") is negative (a variance)");
        }
}

// The inputs in planar form (see denoise.h for the symbols).
struct Prepared {
    int w, h;
    // Images filtered: 2 (half_a, half_b) or 1 (color, with its variance).
    int nh;
    // Whether any feature variance was given (fvar holds them, else it is empty).
    bool has_fvar;
    // 0..2: X_a / m, 3..5: X_b / m, rows of ws = w + 2 kPad floats with the image at columns
    // [kPad, kPad + w) and zeros around it, so that the filter's 8-pixel loads at a neighbour
    // offset stay inside the plane (their weight is 0 outside the image).
    int ws;
    ZeroBuffer half;
    Planes var;  // 0: V
    // 0..2 albedo / s_a, 3..5 normal / s_n, 6 inverse depth u, 7 1 / (s_z u)^2, 8..9 du/dx,
    // du/dy
    Planes feat;
    Planes mod;  // 0..2 the albedo divided out (1 where below kMinAlbedo)
    // 0 sum of the albedo's channel variances / s_a^2, 1 the same for the normal / s_n^2,
    // 2 the variance of u (a pixel's own, for the cancellation in f)
    Planes fvar;
    Prepared(int w_, int h_, int nh_, bool has_fvar_)
        : w(w_),
          h(h_),
          nh(nh_),
          has_fvar(has_fvar_),
          ws(w_ + 2 * kPad),
          half(std::size_t(ws) * h_ * 3 * nh_),
          var(std::size_t(w_) * h_, 1),
          feat(std::size_t(w_) * h_, 10),
          mod(std::size_t(w_) * h_, 3),
          fvar(has_fvar_ ? std::size_t(w_) * h_ : 0, 3) {}
    // Row y of half plane k, indexed by column x in [-kPad, w + kPad).
    float* hrow(int k, int y) { return half.data() + (std::size_t(k) * h + y) * ws + kPad; }
    const float* hrow(int k, int y) const {
        return half.data() + (std::size_t(k) * h + y) * ws + kPad;
    }
};

void prepare(const DenoiseInput& in, Prepared& p, int threads) {
    const int w = p.w, h = p.h;
    ZeroBuffer raw_var(std::size_t(w) * h);
    run_parallel(threads, h, [&](int y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            const Rgb a = in.albedo->at(x, y), n = in.normal->at(x, y);
            // The first hits differ in normal or depth (see kMinAlbedo): not divided out.
            bool mixed = false;
            if (in.normal_variance != nullptr) {
                const Rgb nv = in.normal_variance->at(x, y);
                mixed = nv.x + nv.y + nv.z > 0.f;
            }
            if (in.depth_variance != nullptr) {
                const float z = in.depth->at(x, y).r;
                mixed = mixed ||
                        (z > 0.f && z < 0.5f * kMissDepth && in.depth_variance->at(x, y).r > 0.f);
            }
            float v = 0.f;
            for (int c = 0; c < 3; ++c) {
                const float m = a[c] > kMinAlbedo && !mixed ? a[c] : 1.f;
                p.mod[c][i] = m;
                if (p.nh == 2) {
                    // V of one half: E[(X - Y)^2] / 2, X and Y independent of one variance.
                    const float xa = in.half_a->at(x, y)[c], xb = in.half_b->at(x, y)[c];
                    p.hrow(c, y)[x] = xa / m;
                    p.hrow(3 + c, y)[x] = xb / m;
                    const float d = (xa - xb) / m;
                    v += 0.5f * d * d;
                } else {
                    p.hrow(c, y)[x] = in.color->at(x, y)[c] / m;
                    v += in.variance->at(x, y)[c] / (m * m);
                }
                p.feat[c][i] = a[c] / kAlbedoBandwidth;
                p.feat[3 + c][i] = n[c] / kNormalBandwidth;
            }
            raw_var.data()[i] = v / 3.f;
            // Inverse depth u = 1 / z (0 where nothing is hit): affine in screen position over
            // a plane seen by a perspective camera, so a plane predicts its neighbours exactly.
            const float z = in.depth->at(x, y).r;
            const float u = z > 0.f && z < 0.5f * kMissDepth ? 1.f / z : 0.f;
            p.feat[6][i] = u;
            const float s = kDepthBandwidth * std::max(u, 1e-12f);
            p.feat[7][i] = 1.f / (s * s);
            if (p.has_fvar) {
                // Feature variances in the units of f: per channel / bandwidth^2, summed; for
                // u = 1 / z, Var(u) ~ Var(z) / z^4 (first order). The depth term's scale
                // widens by the pixel's own variance.
                auto sum = [&](const Image* img) {
                    if (img == nullptr) return 0.f;
                    const Rgb& c = img->at(x, y);
                    return c.r + c.g + c.b;
                };
                p.fvar[0][i] = sum(in.albedo_variance) / (kAlbedoBandwidth * kAlbedoBandwidth);
                p.fvar[1][i] = sum(in.normal_variance) / (kNormalBandwidth * kNormalBandwidth);
                const float vz = in.depth_variance != nullptr ? in.depth_variance->at(x, y).r : 0.f;
                const float vu = u > 0.f ? vz * (u * u) * (u * u) : 0.f;
                p.fvar[2][i] = vu;
                p.feat[7][i] = 1.f / (s * s + vu);
            }
        }
    });
    box_mean(raw_var.data(), p.var[0], w, h, 1);
    // du/dx and du/dy: of the two one-sided differences the smaller (a surface's own slope,
    // not the jump to the surface behind an edge).
    const float* u = p.feat[6];
    auto slope = [](float back, float fwd) {
        return std::fabs(back) < std::fabs(fwd) ? back : fwd;
    };
    run_parallel(threads, h, [&](int y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            const float r = x + 1 < w ? u[i + 1] - u[i] : 0.f;
            const float l = x > 0 ? u[i] - u[i - 1] : r;
            const float b = y + 1 < h ? u[i + w] - u[i] : 0.f;
            const float t = y > 0 ? u[i] - u[i - w] : b;
            p.feat[8][i] = slope(l, x + 1 < w ? r : l);
            p.feat[9][i] = slope(t, y + 1 < h ? b : t);
        }
    });
}

// Eight floats, one AVX register (two SSE ones in the baseline clone). Lane-wise IEEE
// arithmetic: the same bits as the scalar expressions.
using V8 = float __attribute__((vector_size(32)));
using I8 = std::int32_t __attribute__((vector_size(32)));
constexpr int kLanes = 8;

[[gnu::always_inline]] inline V8 load8(const float* p) {
    V8 v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
[[gnu::always_inline]] inline void store8(float* p, V8 v) {
    std::memcpy(p, &v, sizeof v);
}
[[gnu::always_inline]] inline V8 splat8(float x) {
    return V8{} + x;
}

// exp(x) for x <= 0, lane-wise: 2^t as 2^floor(t) times a degree-5 polynomial of 2^f on
// [0, 1) (relative error below 1e-6), and exactly 0 for x <= -80 (exp(-80) ~ 1.8e-35: a weight
// of 0 marks a neighbour outside the image). Weights need no more accuracy; libm's expf would
// not vectorise.
[[gnu::always_inline]] inline V8 exp_neg8(V8 x) {
    const V8 lo = splat8(-80.f);
    const I8 keep = x > lo;
    x = keep ? x : lo;
    const V8 t = x * 1.44269504f + 128.f;  // in [12.5, 128]: truncation is floor
    const I8 i = __builtin_convertvector(t, I8);
    const V8 f = t - __builtin_convertvector(i, V8);
    const V8 p =
        1.f + f * (0.69314718f +
                   f * (0.24022652f + f * (0.05550411f + f * (0.00961813f + f * 0.00133336f))));
    const I8 bits = (i - 1) << 23;  // 2^(i - 128), exponent field i - 1
    V8 scale;
    std::memcpy(&scale, &bits, sizeof scale);
    return keep ? p * scale : V8{};
}

// Per-thread scratch of filter_tile, sized for the largest tile.
struct TileScratch {
    std::vector<float> d, dh, dist, feat, acc;
};

// Accumulators of the weighted first-order fit, per slot (2 halves x kCandidates): the weight
// moments sum w (1, dx, dy, dx^2, dy^2, dx dy) and the value moments sum w X_c (1, dx, dy) per
// channel.
constexpr int kMoments = 6 + 9;
// The feature distance of a neighbour outside the image: its weight exp(-f) is 0.
constexpr float kFar = 1e30f;

// The filtered halves F_k of one tile, rows [y0, y1) x columns [x0, x1), into out (planes
// (half * kCandidates + k) * 3 + c), and their squared differences from the other half,
// summed over channels, into err (plane half * kCandidates + k). Per row of offsets dy, the patch
// distances d and feature distances f of all the row's offsets dx are computed first; then per 8
// pixels the sums over dx are kept in registers and added to the tile's accumulators once per dy.
// Compiled for the baseline ISA and AVX2 with the same bits (no FMA contraction in this file).
FACET_TARGET_CLONES
void filter_tile(const Prepared& p, int radius, int y0, int y1, int x0, int x1, Planes& out,
                 Planes& err, TileScratch& s) {
    const int w = p.w, h = p.h;
    // The patch distance needs one row and column of margin around the tile.
    const int m0 = std::max(0, y0 - 1), m1 = std::min(h, y1 + 1);
    const int c0 = std::max(0, x0 - 1), c1 = std::min(w, x1 + 1);
    const int mrows = m1 - m0, mw = c1 - c0, rows = y1 - y0, tw = x1 - x0;
    // Tile rows padded to whole vectors; the lanes past tw get d = 0, f = kFar (weight 0).
    const int tv = (tw + kLanes - 1) / kLanes, tp = tv * kLanes;
    const int nd = 2 * radius + 1;
    const std::size_t ms = std::size_t(mrows) * mw, hs = std::size_t(mrows) * tw,
                      bs = std::size_t(rows) * tp;
    s.d.resize(2 * ms);
    s.dh.resize(2 * hs);
    s.dist.assign(2 * nd * bs, 0.f);  // [half][dx][row][column]: d after its 3 x 3 box
    s.feat.assign(nd * bs, kFar);     // [dx][row][column]: f
    s.acc.assign(std::size_t(2 * kCandidates * kMoments) * bs, 0.f);
    float inv_k2[kCandidates];
    for (int k = 0; k < kCandidates; ++k) inv_k2[k] = 1.f / (kStrengths[k] * kStrengths[k]);
    const float* V = p.var[0];

    for (int dy = -radius; dy <= radius; ++dy) {
        for (int dx = -radius; dx <= radius; ++dx) {
            const int di = dx + radius;
            // d(p, p + (dx, dy)) with the neighbour clamped into the image (the patch's
            // border), per half.
            for (int y = m0; y < m1; ++y) {
                const int qy = std::clamp(y + dy, 0, h - 1);
                for (int hh = 0; hh < p.nh; ++hh) {
                    const float* X0 = p.hrow(3 * hh, y);
                    const float* X1 = p.hrow(3 * hh + 1, y);
                    const float* X2 = p.hrow(3 * hh + 2, y);
                    const float* Q0 = p.hrow(3 * hh, qy);
                    const float* Q1 = p.hrow(3 * hh + 1, qy);
                    const float* Q2 = p.hrow(3 * hh + 2, qy);
                    const float* Vp = V + std::size_t(y) * w;
                    const float* Vq = V + std::size_t(qy) * w;
                    float* D = s.d.data() + hh * ms + std::size_t(y - m0) * mw;
                    // Columns whose neighbour is inside the image, and the clamped rest.
                    const int in_lo = std::clamp(-dx, c0, c1), in_hi = std::clamp(w - dx, c0, c1);
                    auto one = [&](int x, int qx) {
                        const float a = X0[x] - Q0[qx], b = X1[x] - Q1[qx], c = X2[x] - Q2[qx];
                        const float vp = Vp[x], vq = Vq[qx];
                        D[x - c0] =
                            ((a * a + b * b + c * c) * (1.f / 3.f) - (vp + std::min(vp, vq))) /
                            (kEpsilon + vp + std::min(vp, vq));
                    };
                    for (int x = c0; x < in_lo; ++x) one(x, std::clamp(x + dx, 0, w - 1));
#pragma GCC ivdep
                    for (int x = in_lo; x < in_hi; ++x) {
                        const int qx = x + dx;
                        const float a = X0[x] - Q0[qx], b = X1[x] - Q1[qx], c = X2[x] - Q2[qx];
                        const float vp = Vp[x], vq = Vq[qx];
                        const float m = vp < vq ? vp : vq;
                        D[x - c0] = ((a * a + b * b + c * c) * (1.f / 3.f) - (vp + m)) /
                                    (kEpsilon + vp + m);
                    }
                    for (int x = std::max(in_hi, in_lo); x < c1; ++x)
                        one(x, std::clamp(x + dx, 0, w - 1));
                }
            }
            for (int hh = 0; hh < p.nh; ++hh) {
                for (int y = 0; y < mrows; ++y) {
                    // D at column x is Dm[x - c0], H at x is Hm[x - x0].
                    const float* Dm = s.d.data() + hh * ms + std::size_t(y) * mw;
                    float* Hm = s.dh.data() + hh * hs + std::size_t(y) * tw;
                    if (w == 1) {
                        Hm[0] = Dm[0];
                        continue;
                    }
                    const int lo = std::max(x0, 1), hi = std::min(x1, w - 1);
                    if (x0 == 0) Hm[0] = 0.5f * (Dm[0] + Dm[1]);
                    const float* Dc = Dm + (lo - c0);
                    float* Hc = Hm + (lo - x0);
                    for (int j = 0; j < hi - lo; ++j)
                        Hc[j] = (Dc[j - 1] + Dc[j] + Dc[j + 1]) * (1.f / 3.f);
                    if (x1 == w) Hm[w - 1 - x0] = 0.5f * (Dm[w - 2 - c0] + Dm[w - 1 - c0]);
                }
                for (int y = y0; y < y1; ++y) {
                    const int a = std::max(y - 1, m0), b = std::min(y + 1, m1 - 1);
                    float* P = s.dist.data() + (std::size_t(hh * nd + di) * rows + (y - y0)) * tp;
                    const float inv = 1.f / float(b - a + 1);
                    for (int x = 0; x < tw; ++x) P[x] = 0.f;
                    for (int r = a; r <= b; ++r) {
                        const float* H = s.dh.data() + hh * hs + std::size_t(r - m0) * tw;
                        for (int x = 0; x < tw; ++x) P[x] += H[x];
                    }
                    // d <= 0 is a perfect match (variance cancellation can undershoot).
                    for (int x = 0; x < tw; ++x) P[x] = std::max(P[x] * inv, 0.f);
                }
            }
            // f for the pixels whose neighbour lies inside the image (tile columns
            // j = x - x0); the rest keep kFar.
            const float fdx = float(dx), fdy = float(dy);
            const int j_lo = std::max(x0, -dx) - x0, j_hi = std::min(x1, w - dx) - x0;
            for (int y = y0; y < y1; ++y) {
                const int qy = y + dy;
                if (qy < 0 || qy >= h) continue;
                const std::size_t row = std::size_t(y) * w + x0,
                                  qrow = std::size_t(qy) * w + x0 + dx;
                const float* F[10];
                const float* G[7];
                for (int f = 0; f < 10; ++f) F[f] = p.feat[f] + row;
                for (int f = 0; f < 7; ++f) G[f] = p.feat[f] + qrow;
                float* FD = s.feat.data() + (std::size_t(di) * rows + (y - y0)) * tp;
                // Named rows (not arrays of pointers) so that GCC vectorises the loops.
                const float *A0 = F[0], *A1 = F[1], *A2 = F[2], *N0 = F[3], *N1 = F[4], *N2 = F[5],
                            *U = F[6], *S = F[7], *Ux = F[8], *Uy = F[9];
                const float *B0 = G[0], *B1 = G[1], *B2 = G[2], *M0 = G[3], *M1 = G[4], *M2 = G[5],
                            *Uq = G[6];
                if (!p.has_fvar) {
#pragma GCC ivdep
                    for (int j = j_lo; j < j_hi; ++j) {
                        // Grouped as below, so that zero feature variances give the same bits.
                        const float a0 = A0[j] - B0[j], a1 = A1[j] - B1[j], a2 = A2[j] - B2[j];
                        const float n0 = N0[j] - M0[j], n1 = N1[j] - M1[j], n2 = N2[j] - M2[j];
                        const float ea = a0 * a0 + a1 * a1 + a2 * a2;
                        const float en = n0 * n0 + n1 * n1 + n2 * n2;
                        const float ez = Uq[j] - U[j] - Ux[j] * fdx - Uy[j] * fdy;
                        FD[j] = ea + en + ez * ez * S[j];
                    }
                    continue;
                }
                // Noisy features: each term's squared difference less the variance it expects
                // from noise (Var_p + min(Var_p, Var_q), as for the colour), over its
                // bandwidth widened by the pixel's own variance (in units of the bandwidth
                // here: 1 + Var_p).
                const float *Wa = p.fvar[0] + row, *Wn = p.fvar[1] + row, *Wu = p.fvar[2] + row;
                const float *Qa = p.fvar[0] + qrow, *Qn = p.fvar[1] + qrow, *Qu = p.fvar[2] + qrow;
#pragma GCC ivdep
                for (int j = j_lo; j < j_hi; ++j) {
                    const float a0 = A0[j] - B0[j], a1 = A1[j] - B1[j], a2 = A2[j] - B2[j];
                    const float n0 = N0[j] - M0[j], n1 = N1[j] - M1[j], n2 = N2[j] - M2[j];
                    const float ea = a0 * a0 + a1 * a1 + a2 * a2;
                    const float en = n0 * n0 + n1 * n1 + n2 * n2;
                    const float ez = Uq[j] - U[j] - Ux[j] * fdx - Uy[j] * fdy;
                    const float va = Wa[j], vn = Wn[j], vu = Wu[j];
                    const float xa = ea - (va + (va < Qa[j] ? va : Qa[j]));
                    const float xn = en - (vn + (vn < Qn[j] ? vn : Qn[j]));
                    const float xz = ez * ez - (vu + (vu < Qu[j] ? vu : Qu[j]));
                    FD[j] = (xa > 0.f ? xa : 0.f) / (1.f + va) +
                            (xn > 0.f ? xn : 0.f) / (1.f + vn) + (xz > 0.f ? xz : 0.f) * S[j];
                }
            }
        }
        // w_k = min(exp(-d / k^2), exp(-f)) = exp(-max(d / k^2, f)); per 8 pixels the sums
        // over dx of w (1, dx, dx^2) and w X_c (1, dx), then the moments with dy.
        const float fdy = float(dy);
        for (int y = y0; y < y1; ++y) {
            const int qy = y + dy;
            if (qy < 0 || qy >= h) continue;
            const std::size_t brow = std::size_t(y - y0) * tp;
            for (int hh = 0; hh < p.nh; ++hh) {
                const float* Q0 = p.hrow(3 * hh, qy) + x0;
                const float* Q1 = p.hrow(3 * hh + 1, qy) + x0;
                const float* Q2 = p.hrow(3 * hh + 2, qy) + x0;
                const float* Dist = s.dist.data() + std::size_t(hh * nd) * bs + brow;
                const float* Feat = s.feat.data() + brow;
                for (int k = 0; k < kCandidates; ++k) {
                    const V8 ik = splat8(inv_k2[k]);
                    float* A =
                        s.acc.data() + std::size_t((hh * kCandidates + k) * kMoments) * bs + brow;
                    for (int v = 0; v < tv; ++v) {
                        const int j = v * kLanes;
                        V8 s0{}, s1{}, s2{}, t00{}, t01{}, t10{}, t11{}, t20{}, t21{};
                        for (int di = 0; di < nd; ++di) {
                            const float fdx = float(di - radius);
                            const V8 d = load8(Dist + std::size_t(di) * bs + j) * ik;
                            const V8 f = load8(Feat + std::size_t(di) * bs + j);
                            const V8 wt = exp_neg8(-(d > f ? d : f));
                            const V8 wx = wt * fdx;
                            s0 += wt;
                            s1 += wx;
                            s2 += wx * fdx;
                            const int q = j + di - radius;
                            const V8 q0 = load8(Q0 + q), q1 = load8(Q1 + q), q2 = load8(Q2 + q);
                            t00 += wt * q0;
                            t01 += wx * q0;
                            t10 += wt * q1;
                            t11 += wx * q1;
                            t20 += wt * q2;
                            t21 += wx * q2;
                        }
                        auto add = [&](int m, V8 x) {
                            float* a = A + std::size_t(m) * bs + j;
                            store8(a, load8(a) + x);
                        };
                        add(0, s0);
                        add(1, s1);
                        add(2, s0 * fdy);
                        add(3, s2);
                        add(4, s0 * fdy * fdy);
                        add(5, s1 * fdy);
                        add(6, t00);
                        add(7, t01);
                        add(8, t00 * fdy);
                        add(9, t10);
                        add(10, t11);
                        add(11, t10 * fdy);
                        add(12, t20);
                        add(13, t21);
                        add(14, t20 * fdy);
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
    for (int slot = 0; slot < p.nh * kCandidates; ++slot) {
        const float* A = s.acc.data() + std::size_t(slot * kMoments) * bs;
        const int other = 3 * (1 - slot / kCandidates);
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) {
                const std::size_t b = std::size_t(y - y0) * tp + (x - x0),
                                  i = std::size_t(y) * w + x;
                auto m = [&](int k) { return double(A[std::size_t(k) * bs + b]); };
                const double s0 = m(0), sx = m(1), sy = m(2);
                const double sxx = m(3) + kRidge * s0, syy = m(4) + kRidge * s0, sxy = m(5);
                // First row of the inverse of [[s0 sx sy] [sx sxx sxy] [sy sxy syy]].
                const double e0 = sxx * syy - sxy * sxy, e1 = sy * sxy - sx * syy,
                             e2 = sx * sxy - sy * sxx;
                const double det = s0 * e0 + sx * e1 + sy * e2;
                const bool plane = det > 1e-9 * s0 * e0 && e0 > 0.0;
                float e = 0.f;
                for (int c = 0; c < 3; ++c) {
                    const double v0 = m(6 + 3 * c), vx = m(7 + 3 * c), vy = m(8 + 3 * c);
                    const double fit = plane ? (e0 * v0 + e1 * vx + e2 * vy) / det : v0 / s0;
                    out[3 * slot + c][i] = float(fit);
                    const float r = float(fit) - p.hrow(p.nh == 2 ? other + c : c, y)[x];
                    e += r * r;
                }
                // One image: (F - X)^2 is biased low by 2 Var(X) dF/dX_p; Stein's unbiased
                // risk estimate adds it back, with dF/dX_p the fit's weight on the pixel's own
                // value (the hat matrix' diagonal: the centre's weight is 1 and its offset 0,
                // so it is the (0, 0) entry of the moment matrix' inverse), the weights held
                // fixed. Var(X) summed over channels is 3 V.
                if (p.nh == 1) e += 2.f * float(plane ? e0 / det : 1.0 / s0) * 3.f * V[i];
                err[slot][i] = e;
            }
    }
}

}  // namespace

Image denoise(const DenoiseInput& in, const DenoiseOptions& o) {
    // The beauty: two half-buffers, or the colour and its variance.
    const bool halves = in.color == nullptr && in.variance == nullptr;
    if (!halves && (in.half_a != nullptr || in.half_b != nullptr))
        throw std::invalid_argument(
            std::string("denoise: ") + (in.color != nullptr ? "color" : "variance") +
            ": give either half_a and half_b, or color and variance, not both");
    if (!halves && in.color == nullptr)
        throw std::invalid_argument(
            "denoise: color: missing (variance given without the colour it belongs to)");
    const Image* first = halves ? in.half_a : in.color;
    const char* first_name = halves ? "half_a" : "color";
    if (first == nullptr || first->width() == 0 || first->height() == 0)
        throw std::invalid_argument(std::string("denoise: ") + first_name +
                                    ": missing (empty image)");
    const Image& ref = *first;
    if (halves) {
        check_input(in.half_a, "half_a", ref, first_name);
        check_input(in.half_b, "half_b", ref, first_name);
    } else {
        check_input(in.color, "color", ref, first_name);
        check_input(in.variance, "variance", ref, first_name, true);
    }
    check_input(in.albedo, "albedo", ref, first_name);
    check_input(in.normal, "normal", ref, first_name);
    check_input(in.depth, "depth", ref, first_name);
    if (in.albedo_variance != nullptr)
        check_input(in.albedo_variance, "albedo_variance", ref, first_name, true);
    if (in.normal_variance != nullptr)
        check_input(in.normal_variance, "normal_variance", ref, first_name, true);
    if (in.depth_variance != nullptr)
        check_input(in.depth_variance, "depth_variance", ref, first_name, true);
    const bool has_fvar = in.albedo_variance != nullptr || in.normal_variance != nullptr ||
                          in.depth_variance != nullptr;
    if (o.radius < 1 || o.radius > 20)
        throw std::invalid_argument("denoise: radius: expected 1..20, got " +
                                    std::to_string(o.radius));
    if (o.threads < 0)
        throw std::invalid_argument("denoise: threads: expected >= 0, got " +
                                    std::to_string(o.threads));
    const int w = ref.width(), h = ref.height();
    const std::size_t n = std::size_t(w) * h;
    const FlushDenormals ftz;
    const int nh = halves ? 2 : 1;
    Prepared p(w, h, nh, has_fvar);
    prepare(in, p, o.threads);

    // The candidates F_k and their error estimates E_k per half against the other half,
    // then E_k averaged over a box (in place).
    Planes filtered(n, nh * kCandidates * 3), err(n, nh * kCandidates);
    const int bands = (h + kBandRows - 1) / kBandRows, cols = (w + kTileCols - 1) / kTileCols;
    tbb::enumerable_thread_specific<TileScratch> scratch;
    run_parallel(o.threads, bands * cols, [&](int t) {
        const int b = t / cols, c = t % cols;
        filter_tile(p, o.radius, b * kBandRows, std::min(h, (b + 1) * kBandRows), c * kTileCols,
                    std::min(w, (c + 1) * kTileCols), filtered, err, scratch.local());
    });
    run_parallel(o.threads, nh * kCandidates,
                 [&](int slot) { box_mean(err[slot], err[slot], w, h, kErrorRadius); });

    Image out(w, h);
    run_parallel(o.threads, h, [&](int y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            Rgb sum(0.f);
            for (int hh = 0; hh < nh; ++hh) {
                int best = 0;
                for (int k = 1; k < kCandidates; ++k)
                    if (err[hh * kCandidates + k][i] < err[hh * kCandidates + best][i]) best = k;
                const int slot = hh * kCandidates + best;
                for (int c = 0; c < 3; ++c) sum[c] += filtered[3 * slot + c][i];
            }
            const float scale = nh == 2 ? 0.5f : 1.f;
            for (int c = 0; c < 3; ++c) out.at(x, y)[c] = scale * sum[c] * p.mod[c][i];
        }
    });
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
    // Alpha (film transparency, holdouts) is not denoised: the render's own.
    if (out.raw.has_alpha()) out.image.alpha() = out.raw.alpha();
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
    ao.variances = options.feature_variances;
    out.features = render_aovs(scene, ao);
    const Aovs& f = out.features;
    DenoiseInput in{&half_a, &half_b, &f.albedo, &f.normal, &f.depth};
    if (options.feature_variances) {
        in.albedo_variance = &f.albedo_variance;
        in.normal_variance = &f.normal_variance;
        in.depth_variance = &f.depth_variance;
    }
    out.image = denoise(in, options);
    return out;
}

}  // namespace facet::render
