// Private to facet_render: the Builder behind build_scene (SceneDescription -> Scene). One
// object carries the state of one build (the scene being filled, the named materials and
// media, the image cache, the pending instances); its member functions are defined by topic,
// one file each, and the declarations below are grouped by that file:
//  - scene_build.cpp: the driver (build()), camera, motion blur and render settings;
//  - build_materials.cpp: media, materials, textures, opacity, the staging of textured
//    materials;
//  - build_shapes.cpp: shapes, prototypes and instances, coordinate and degenerate checks;
//  - build_lights.cpp: lights;
//  - scene_analysis.cpp: the scene analysis (SceneFeatures).
// Every error is a SceneError "<name>: <path>: <message>" (fail()).
#pragma once

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "facet/render/scene_description.h"
#include "facet/render/texel_pages.h"
#include "kind_build.h"
#include "scene_checks.h"
#include "scene_impl.h"

namespace facet::render::detail {

// Largest |component| of a vector, in double.
inline double max_abs(const glm::dvec3& v) {
    return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
}

class Builder final : public BuildChecks {
  public:
    Builder(const SceneDescription& desc, std::string name, const SceneLimits& limits,
            BuildReport* report);

    Scene build();

    [[noreturn]] void fail(const std::string& pointer, const std::string& message) const override;

  private:
    // A built material: the Material (for textured ones, built from every texture's largest
    // value: the scene analysis reads its lobes) and the index of its TexturedMaterial or -1.
    struct BuiltMaterial {
        const Material* material = nullptr;
        std::int32_t textured = -1;
        std::shared_ptr<const Material> shared = {};  // the same material, for combinations
        Opacity opacity = {};                         // the material's "opacity" and "alpha_cutoff"
        std::int32_t interior = -1;                   // its "interior" medium (Scene::media())
    };

    struct PendingInstance {
        std::uint32_t shape, prototype;
        glm::dmat4 xf;
        bool described;  // prototype indexes the description's prototypes (else Impl's)
        std::vector<DecomposedTransform> motion = {};  // a moving placement (InstanceGeom)
    };

    // What the kinds' builders get (kind_build.h, textures/texture_build.h), each defined in
    // the file of its kind.
    class MediumContext;   // build_materials.cpp
    class TextureContext;  // build_materials.cpp
    class ShapeContext;    // build_shapes.cpp
    class LightContext;    // build_lights.cpp

    // --- scene_build.cpp: camera, motion blur, render settings ---------------------------------

    void build_camera();
    void build_motion();
    double checked_aperture_radius(const CameraDesc& c, const std::string& ptr,
                                   Projection proj) const;
    void build_render();

    // Motion steps beyond this are an error (Blender's Steps 1..7 give 2^Steps + 1 <= 129).
    static constexpr std::size_t kMaxMotionSteps = 1024;
    static constexpr std::size_t kMaxShutterCurve = 65536;

    // --- build_materials.cpp: media, materials, textures, opacity, staging --------------------

    std::string unknown_medium(const std::string& name) const;
    void build_media();
    std::int32_t take_interior(MaterialDesc& m, const std::string& ptr);
    Opacity build_opacity(MaterialDesc& m, const std::string& ptr);
    std::shared_ptr<const TexelImage> load_image(const TextureDesc& d, const TexelImageOptions& opt,
                                                 const std::string& ptr);
    std::string unknown_material(const std::string& name) const;
    BuiltMaterial named_material(const std::string& name, const std::string& ref_ptr);
    std::vector<BuiltMaterial> build_children(const MaterialDesc& m, const ModelInfo& info,
                                              const std::string& ptr);
    void check_energy_gain(const MaterialDesc& m, const Material& mat, const std::string& ptr);
    void check_nested_subsurface(const MaterialDesc& m, const std::vector<BuiltMaterial>& children,
                                 const std::string& ptr);
    static std::string fmt_number(double v);
    const Texture* build_texture(const TextureDesc& d, const std::string& ptr, bool color,
                                 bool radiance);
    BuiltMaterial build_material(const MaterialDesc& desc, const std::string& ptr,
                                 const MaterialConversion* conversion = nullptr);
    BuiltMaterial build_model(const MaterialDesc& m, const std::string& ptr,
                              const MaterialConversion* conversion);
    static void stage(TexturedMaterial& tm, const Material& base,
                      const MaterialConversion* conversion);
    void build_materials();
    const Material* black_material();

    // --- build_shapes.cpp: shapes, prototypes, instances --------------------------------------

    std::string shape_place(std::uint32_t index) const;
    bool needs_uv(const ShapeSurface& s);
    void set_texture_space(ShapeInfo& info, const ShapeDesc& s, const Bounds3& bounds,
                           const std::string& ptr);
    bool needs_position(const ShapeSurface& s);
    bool needs_view(const ShapeSurface& s);
    bool needs_strand(const ShapeSurface& s);
    bool needs_color(const ShapeSurface& s);
    void build_shape(const ShapeDesc& s, std::uint32_t index, const std::string& ptr,
                     std::int32_t proto);
    std::vector<DecomposedTransform> shape_motion(const ShapeDesc& s, const std::string& ptr,
                                                  std::int32_t proto);
    bool shape_deformation(const ShapeDesc& s, const std::string& ptr, std::int32_t proto);
    void build_prototypes();
    void place_instance(const PendingInstance& pi);
    void check_coordinate_range(double m, std::uint32_t index);
    void drop_degenerate(TriangleMesh& mesh, std::uint32_t index);
    void reserve_triangles(std::uint64_t n, const std::string& ptr);

    // Embree's limit on a geometry's time steps (RTC_MAX_TIME_STEP_COUNT).
    static constexpr std::size_t kMaxDeformSteps = 129;

    // --- build_lights.cpp ----------------------------------------------------------------------

    void build_light(const LightDesc& l, std::size_t index);

    // --- scene_analysis.cpp --------------------------------------------------------------------

    static bool reflects(const Material& m);
    bool maybe_visible(const Bounds3& b) const;
    void analyse();

    // --- the build's state ---------------------------------------------------------------------

    const SceneDescription& m_desc;
    std::string m_name;
    SceneLimits m_limits;
    BuildReport* m_report;
    std::uint64_t m_triangles = 0, m_degenerate = 0;
    Scene::Builder m_builder;
    std::map<std::string, BuiltMaterial> m_named;
    std::map<std::string, const MaterialDesc*> m_named_desc;  // every named material
    std::map<std::string, std::int32_t> m_medium_index;       // medium name -> Scene::media()
    std::vector<std::string> m_building;  // named materials being built (cycle detection)
    TexelImageCache m_images;             // an image used twice is read once
    const Material* m_black = nullptr;
    std::vector<Bounds3> m_shape_bounds;
    std::vector<std::string> m_places;       // shape_place() per Scene::shapes() index
    std::vector<PendingInstance> m_pending;  // instances, placed once their prototypes are built
    bool m_motion_on = false;                // "motion_blur" given and enabled
    bool m_camera_moves = false;             // with motion blur on: the camera has a motion
    bool m_shapes_move = false;              // with motion blur on: some shape has a motion
    std::size_t m_prototype_base = 0;        // Impl::prototypes index of the first described
};

}  // namespace facet::render::detail
