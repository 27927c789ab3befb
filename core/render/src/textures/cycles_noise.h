// Blender / Cycles 3.4's procedural building blocks, in float as Cycles evaluates them, so that
// Facet's procedural textures give Cycles' values to float precision:
//  - the hash: Bob Jenkins' lookup3 (2006) final mix of 1-4 32-bit keys, seeded with
//    0xdeadbeef + (n << 2) + 13 for n keys; hash_*_to_float divides by 2^32 - 1; float keys
//    are hashed by their bit patterns;
//  - Perlin's improved gradient noise (Perlin 2002) in 1-4D with Cycles' gradient sets, its
//    quintic fade and its per-dimension scale factors (0.25, 0.6616, 0.982, 0.8344) that bring
//    the signed noise to about [-1, 1]; "noise" is 0.5 + 0.5 signed noise;
//  - fBm (fractal_noise_*): octaves at doubling frequency weighted by roughness^i, normalised
//    by the sum of the weights, the fractional part of Detail blending in one more octave.
// Cycles' floor for the lattice cell is float_to_int(x) - (x < 0): a negative integer x lands
// in the cell below (fraction 1), not floor(x); kept for bit-equal cells.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace facet::render::cycles {

using glm::vec2;
using glm::vec3;
using glm::vec4;

inline std::uint32_t rot(std::uint32_t x, int k) {
    return (x << k) | (x >> (32 - k));
}

// lookup3's mix() and final().
inline void hash_mix(std::uint32_t& a, std::uint32_t& b, std::uint32_t& c) {
    a -= c, a ^= rot(c, 4), c += b;
    b -= a, b ^= rot(a, 6), a += c;
    c -= b, c ^= rot(b, 8), b += a;
    a -= c, a ^= rot(c, 16), c += b;
    b -= a, b ^= rot(a, 19), a += c;
    c -= b, c ^= rot(b, 4), b += a;
}
inline void hash_final(std::uint32_t& a, std::uint32_t& b, std::uint32_t& c) {
    c ^= b, c -= rot(b, 14);
    a ^= c, a -= rot(c, 11);
    b ^= a, b -= rot(a, 25);
    c ^= b, c -= rot(b, 16);
    a ^= c, a -= rot(c, 4);
    b ^= a, b -= rot(a, 14);
    c ^= b, c -= rot(b, 24);
}

inline std::uint32_t hash_uint(std::uint32_t kx) {
    std::uint32_t a, b, c;
    a = b = c = 0xdeadbeefu + (1u << 2) + 13u;
    a += kx;
    hash_final(a, b, c);
    return c;
}
inline std::uint32_t hash_uint2(std::uint32_t kx, std::uint32_t ky) {
    std::uint32_t a, b, c;
    a = b = c = 0xdeadbeefu + (2u << 2) + 13u;
    b += ky;
    a += kx;
    hash_final(a, b, c);
    return c;
}
inline std::uint32_t hash_uint3(std::uint32_t kx, std::uint32_t ky, std::uint32_t kz) {
    std::uint32_t a, b, c;
    a = b = c = 0xdeadbeefu + (3u << 2) + 13u;
    c += kz;
    b += ky;
    a += kx;
    hash_final(a, b, c);
    return c;
}
inline std::uint32_t hash_uint4(std::uint32_t kx, std::uint32_t ky, std::uint32_t kz,
                                std::uint32_t kw) {
    std::uint32_t a, b, c;
    a = b = c = 0xdeadbeefu + (4u << 2) + 13u;
    a += kx;
    b += ky;
    c += kz;
    hash_mix(a, b, c);
    a += kw;
    hash_final(a, b, c);
    return c;
}

inline std::uint32_t bits(float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    return u;
}
inline float to_unit(std::uint32_t h) {
    return float(h) / float(0xFFFFFFFFu);
}

inline float hash_float(float k) {
    return to_unit(hash_uint(bits(k)));
}
inline float hash_float(vec2 k) {
    return to_unit(hash_uint2(bits(k.x), bits(k.y)));
}
inline float hash_float(vec3 k) {
    return to_unit(hash_uint3(bits(k.x), bits(k.y), bits(k.z)));
}
inline float hash_float(vec4 k) {
    return to_unit(hash_uint4(bits(k.x), bits(k.y), bits(k.z), bits(k.w)));
}
// Cycles' hash_float*_to_float2/3/4: further components hash the key with an extra
// coordinate (or permuted, in 4D).
inline vec2 hash_vec2(vec2 k) {
    return {hash_float(k), hash_float(vec3(k.x, k.y, 1.f))};
}
inline vec3 hash_vec3(float k) {
    return {hash_float(k), hash_float(vec2(k, 1.f)), hash_float(vec2(k, 2.f))};
}
inline vec3 hash_vec3(vec2 k) {
    return {hash_float(k), hash_float(vec3(k.x, k.y, 1.f)), hash_float(vec3(k.x, k.y, 2.f))};
}
inline vec3 hash_vec3(vec3 k) {
    return {hash_float(k), hash_float(vec4(k.x, k.y, k.z, 1.f)),
            hash_float(vec4(k.x, k.y, k.z, 2.f))};
}
inline vec3 hash_vec3(vec4 k) {
    return {hash_float(k), hash_float(vec4(k.z, k.x, k.w, k.y)),
            hash_float(vec4(k.w, k.z, k.y, k.x))};
}
inline vec4 hash_vec4(vec4 k) {
    return {hash_float(k), hash_float(vec4(k.w, k.x, k.y, k.z)),
            hash_float(vec4(k.z, k.w, k.x, k.y)), hash_float(vec4(k.y, k.z, k.w, k.x))};
}

// The lattice cell and the fraction in it (see the header).
inline float floorfrac(float x, int& i) {
    i = int(x) - (x < 0.f ? 1 : 0);
    return x - float(i);
}
inline float fade(float t) {
    return t * t * t * (t * (t * 6.f - 15.f) + 10.f);
}
inline float negate_if(float v, std::uint32_t c) {
    return c ? -v : v;
}
// Cycles' mix(a, b, t).
inline float lerp(float a, float b, float t) {
    return a + t * (b - a);
}

inline float grad1(std::uint32_t hash, float x) {
    const std::uint32_t h = hash & 15u;
    const float g = float(1u + (h & 7u));
    return negate_if(g, h & 8u) * x;
}
inline float grad2(std::uint32_t hash, float x, float y) {
    const std::uint32_t h = hash & 7u;
    const float u = h < 4u ? x : y;
    const float v = 2.f * (h < 4u ? y : x);
    return negate_if(u, h & 1u) + negate_if(v, h & 2u);
}
inline float grad3(std::uint32_t hash, float x, float y, float z) {
    const std::uint32_t h = hash & 15u;
    const float u = h < 8u ? x : y;
    const float vt = (h == 12u || h == 14u) ? x : z;
    const float v = h < 4u ? y : vt;
    return negate_if(u, h & 1u) + negate_if(v, h & 2u);
}
inline float grad4(std::uint32_t hash, float x, float y, float z, float w) {
    const std::uint32_t h = hash & 31u;
    const float u = h < 24u ? x : y;
    const float v = h < 16u ? y : z;
    const float s = h < 8u ? z : w;
    return negate_if(u, h & 1u) + negate_if(v, h & 2u) + negate_if(s, h & 4u);
}

// Signed Perlin noise, unscaled.
float perlin(float x);
float perlin(vec2 p);
float perlin(vec3 p);
float perlin(vec4 p);

// Signed noise in about [-1, 1] (scaled, non-finite values as 0) and noise in about [0, 1].
float snoise(float p);
float snoise(vec2 p);
float snoise(vec3 p);
float snoise(vec4 p);
template <class P>
float noise(P p) {
    return 0.5f * snoise(p) + 0.5f;
}

// fBm of `octaves` (clamped to [0, 15]) octaves with amplitude ratio `roughness` (clamped to
// [0, 1]): Cycles' fractal_noise_*.
template <class P>
float fractal_noise(P p, float octaves, float roughness);

}  // namespace facet::render::cycles
