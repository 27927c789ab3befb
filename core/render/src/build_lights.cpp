// build_scene's lights (scene_builder.h): each entry of "lights" through its kind's builder
// (kinds.h) and the LightContext it adds lights through. Emitting shapes add their area
// lights in build_shapes.cpp.

#include "facet/render/kinds.h"
#include "scene_builder.h"

namespace facet::render::detail {

// What a light kind's builder adds to the scene (kind_build.h).
class Builder::LightContext final : public LightBuild {
  public:
    LightContext(Builder& b, const LightDesc& l, std::string p)
        : LightBuild(l, std::move(p)), m_b(b) {}
    [[noreturn]] void fail(const std::string& p, const std::string& m) const override {
        m_b.fail(p, m);
    }
    bool files_allowed() const override { return m_b.m_limits.allow_files; }
    const std::string& base_dir() const override { return m_b.m_desc.base_dir; }
    void add_light(Light light) override { m_b.m_builder.lights().push_back(std::move(light)); }
    void add_environment(Light light) override {
        if (m_b.m_builder.environment() >= 0) fail(ptr, "only one environment light is allowed");
        m_b.m_builder.environment() = std::int32_t(m_b.m_builder.lights().size());
        add_light(std::move(light));
    }
    void warn(std::string message) override {
        m_b.m_builder.warnings().push_back(std::move(message));
    }

  private:
    Builder& m_b;
};

void Builder::build_light(const LightDesc& l, std::size_t index) {
    LightContext ctx(*this, l, "/lights/" + std::to_string(index));
    const LightKindDef* k = find_light_kind(l.kind);
    if (!k) fail(ctx.ptr + "/type", "unknown light type");
    k->build(ctx);
}

}  // namespace facet::render::detail
