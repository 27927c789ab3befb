// Perlin noise and fBm as Cycles 3.4 evaluates them (cycles_noise.h).
#include "cycles_noise.h"

#include <algorithm>

namespace facet::render::cycles {

namespace {

// Cycles' interpolation of 2^n corner values: x fastest, then y, z (v_i at the corner whose
// offsets are the bits of i).
float bi_mix(float v0, float v1, float v2, float v3, float x, float y) {
    const float x1 = 1.f - x;
    return (1.f - y) * (v0 * x1 + v1 * x) + y * (v2 * x1 + v3 * x);
}
float tri_mix(const float* v, float x, float y, float z) {
    const float x1 = 1.f - x, y1 = 1.f - y, z1 = 1.f - z;
    return z1 * (y1 * (v[0] * x1 + v[1] * x) + y * (v[2] * x1 + v[3] * x)) +
           z * (y1 * (v[4] * x1 + v[5] * x) + y * (v[6] * x1 + v[7] * x));
}

// Non-finite values become 0 (Cycles' ensure_finite).
float finite_or_zero(float v) {
    return std::isfinite(v) ? v : 0.f;
}

}  // namespace

float perlin(float x) {
    int X;
    const float fx = floorfrac(x, X);
    const float u = fade(fx);
    return lerp(grad1(hash_uint(std::uint32_t(X)), fx),
                grad1(hash_uint(std::uint32_t(X + 1)), fx - 1.f), u);
}

float perlin(vec2 p) {
    int X, Y;
    const float fx = floorfrac(p.x, X), fy = floorfrac(p.y, Y);
    const float u = fade(fx), v = fade(fy);
    auto g = [&](int i, int j) {
        return grad2(hash_uint2(std::uint32_t(X + i), std::uint32_t(Y + j)), fx - float(i),
                     fy - float(j));
    };
    return bi_mix(g(0, 0), g(1, 0), g(0, 1), g(1, 1), u, v);
}

float perlin(vec3 p) {
    int X, Y, Z;
    const float fx = floorfrac(p.x, X), fy = floorfrac(p.y, Y), fz = floorfrac(p.z, Z);
    float v[8];
    for (int c = 0; c < 8; ++c) {
        const int i = c & 1, j = (c >> 1) & 1, k = (c >> 2) & 1;
        v[c] = grad3(hash_uint3(std::uint32_t(X + i), std::uint32_t(Y + j), std::uint32_t(Z + k)),
                     fx - float(i), fy - float(j), fz - float(k));
    }
    return tri_mix(v, fade(fx), fade(fy), fade(fz));
}

float perlin(vec4 p) {
    int X, Y, Z, W;
    const float fx = floorfrac(p.x, X), fy = floorfrac(p.y, Y), fz = floorfrac(p.z, Z),
                fw = floorfrac(p.w, W);
    float v[16];
    for (int c = 0; c < 16; ++c) {
        const int i = c & 1, j = (c >> 1) & 1, k = (c >> 2) & 1, l = (c >> 3) & 1;
        v[c] = grad4(hash_uint4(std::uint32_t(X + i), std::uint32_t(Y + j), std::uint32_t(Z + k),
                                std::uint32_t(W + l)),
                     fx - float(i), fy - float(j), fz - float(k), fw - float(l));
    }
    const float u = fade(fx), vv = fade(fy), t = fade(fz), s = fade(fw);
    return lerp(tri_mix(v, u, vv, t), tri_mix(v + 8, u, vv, t), s);
}

float snoise(float p) {
    return 0.2500f * finite_or_zero(perlin(p));
}
float snoise(vec2 p) {
    return 0.6616f * finite_or_zero(perlin(p));
}
float snoise(vec3 p) {
    return 0.9820f * finite_or_zero(perlin(p));
}
float snoise(vec4 p) {
    return 0.8344f * finite_or_zero(perlin(p));
}

template <class P>
float fractal_noise(P p, float octaves, float roughness) {
    float fscale = 1.f, amp = 1.f, maxamp = 0.f, sum = 0.f;
    octaves = std::clamp(octaves, 0.f, 15.f);
    roughness = std::clamp(roughness, 0.f, 1.f);
    const int n = int(octaves);
    for (int i = 0; i <= n; ++i) {
        const float t = noise(fscale * p);
        sum += t * amp;
        maxamp += amp;
        amp *= roughness;
        fscale *= 2.f;
    }
    const float rmd = octaves - std::floor(octaves);
    if (rmd != 0.f) {
        const float t = noise(fscale * p);
        float sum2 = sum + t * amp;
        sum /= maxamp;
        sum2 /= maxamp + amp;
        return (1.f - rmd) * sum + rmd * sum2;
    }
    return sum / maxamp;
}

template float fractal_noise(float, float, float);
template float fractal_noise(vec2, float, float);
template float fractal_noise(vec3, float, float);
template float fractal_noise(vec4, float, float);

}  // namespace facet::render::cycles
