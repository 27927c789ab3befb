// A BxDF of a model unit (core/src/models/<model>.cpp), held in place inside a Material.
//
// A new model is one unit: its BxDF class, its parameter table and its builder (facet/
// registry.h). The Material holds the unit's BxDF through this type-erased box, so adding a
// model edits no Material code: no heap allocation, no virtual base, one indirect call per
// evaluation (the rare models' path; the composite's lobes stay inline in Material).
//
// Conventions: facet/bxdf.h. A unit BxDF type B is trivially copyable, at most kSize bytes, and
// has
//   BSDFEval B::eval(const Vec3& wo, const Vec3& wi) const;            // f and pdf together
//   std::optional<BSDFSample> B::sample_f(const Vec3& wo, float uc, Vec2 u) const;
//   BxDFFlags B::flags() const;
// and may declare `static constexpr bool kReadsTangent = true;` when f depends on the frame's x
// axis (a fibre's direction: the hair models): the renderer then builds the frame from the
// surface's dpdu (Frame::from_z_x), as for anisotropic lobes (Material::anisotropic()).
// A model flagged Transmission follows facet/dielectric.h's frame conventions (z the shape's
// outward normal, wo on either side). Unit models are symmetric in the transport mode (no
// refraction scaling), so the mode is not passed.
#pragma once

#include <cstddef>
#include <new>
#include <optional>
#include <type_traits>

#include "facet/bxdf.h"

namespace facet {

class InlineBxDF {
  public:
    static constexpr std::size_t kSize = 64;

    template <class B>
    explicit InlineBxDF(const B& bxdf) : m_ops(&kOps<B>) {
        static_assert(std::is_trivially_copyable_v<B>, "a unit BxDF must be trivially copyable");
        static_assert(sizeof(B) <= kSize && alignof(B) <= alignof(std::max_align_t),
                      "a unit BxDF must fit InlineBxDF::kSize bytes");
        ::new (static_cast<void*>(m_storage)) B(bxdf);
    }

    BSDFEval eval(const Vec3& wo, const Vec3& wi) const { return m_ops->eval(m_storage, wo, wi); }
    std::optional<BSDFSample> sample_f(const Vec3& wo, float uc, Vec2 u) const {
        return m_ops->sample_f(m_storage, wo, uc, u);
    }
    BxDFFlags flags() const { return m_ops->flags(m_storage); }
    // The unit reads the frame's tangent x (B::kReadsTangent, header comment).
    bool reads_tangent() const { return m_ops->reads_tangent; }
    // The unit's BxDF when it is a B (tests, the unit's own hooks), else null.
    template <class B>
    const B* get() const {
        return m_ops == &kOps<B> ? std::launder(reinterpret_cast<const B*>(m_storage)) : nullptr;
    }

  private:
    struct Ops {
        BSDFEval (*eval)(const void*, const Vec3&, const Vec3&);
        std::optional<BSDFSample> (*sample_f)(const void*, const Vec3&, float, Vec2);
        BxDFFlags (*flags)(const void*);
        bool reads_tangent;
    };
    template <class B>
    static const B& as(const void* p) {
        return *std::launder(static_cast<const B*>(p));
    }
    template <class B>
    static constexpr bool reads_tangent_v = [] {
        if constexpr (requires { B::kReadsTangent; })
            return bool(B::kReadsTangent);
        else
            return false;
    }();
    template <class B>
    static constexpr Ops kOps = {
        [](const void* p, const Vec3& wo, const Vec3& wi) { return as<B>(p).eval(wo, wi); },
        [](const void* p, const Vec3& wo, float uc, Vec2 u) {
            return as<B>(p).sample_f(wo, uc, u);
        },
        [](const void* p) { return as<B>(p).flags(); }, reads_tangent_v<B>};

    alignas(std::max_align_t) std::byte m_storage[kSize];
    const Ops* m_ops;
};

}  // namespace facet
