// `facet export-pov scene.json -o scene.pov [--area-grid N] [--glossy-samples N]
//  [--environment error|background] [--radiosity off|low|medium|high|C,E,R] [--ini scene.ini]`
//
// A thin command over the render library's POV-Ray exporter (facet/render/pov_export.h, which
// documents what is written and why; docs/povray.md shows how to render the result).
#include <CLI/CLI.hpp>

#include <memory>
#include <stdexcept>
#include <string>

#include "commands.h"
#include "facet/render/pov_export.h"
#include "facet/render/scene_description.h"

namespace facet::cli {

namespace {

struct ExportPovOptions {
    std::string scene;
    std::string output;
    std::string ini;
    render::PovExportOptions pov;
};

void run_export_pov(const ExportPovOptions& o) {
    if (o.output.empty()) throw std::runtime_error("export-pov: no output: give -o scene.pov");
    try {
        // A bad --radiosity fails before the scene is read.
        render::check_pov_options(o.pov);
    } catch (const std::invalid_argument& e) {
        throw std::runtime_error(std::string("export-pov: ") + e.what());
    }
    const render::SceneDescription desc = render::read_scene_description(o.scene);
    try {
        render::export_pov_file(desc, o.scene, o.output, o.pov, o.ini);
    } catch (const render::SceneError&) {
        throw;
    } catch (const std::runtime_error& e) {
        throw std::runtime_error(std::string("export-pov: ") + e.what());
    }
}

}  // namespace

void add_export_pov_command(CLI::App& app) {
    auto o = std::make_shared<ExportPovOptions>();
    CLI::App* cmd = app.add_subcommand(
        "export-pov",
        "Write POV-Ray SDL (for povray-facet) that renders what `facet render --integrator "
        "direct` renders of a JSON scene; what POV-Ray cannot express is an error naming the "
        "JSON path");
    cmd->add_option("scene", o->scene, "scene file (.json)")->required();
    cmd->add_option("-o,--output", o->output, "output SDL file (.pov)")->required();
    cmd->add_option(
        "--ini", o->ini,
        "also write a POV-Ray .ini with the size, no antialiasing and 32-bit float EXR output");
    cmd->add_option("--area-grid", o->pov.area_grid,
                    "emitter quadrature: N x N cells per parallelogram quad, N^2 per triangle, "
                    "N rings x 4N sectors per disc; each cell is one light")
        ->check(CLI::Range(1, 64))
        ->capture_default_str();
    cmd->add_option("--glossy-samples", o->pov.glossy_samples,
                    "glossy reflection rays per hit of brdf finishes (POV `samples`; 0 = lights "
                    "only, as the direct integrator)")
        ->check(CLI::Range(0, 10000))
        ->capture_default_str();
    cmd->add_option("--blur-samples", o->pov.blur_samples,
                    "camera rays per pixel of a thin-lens camera's focal_blur (POV "
                    "`blur_samples`; POV-Ray's own aperture sampling)")
        ->check(CLI::Range(1, 4096))
        ->capture_default_str();
    cmd->add_option("--environment", o->pov.environment,
                    "error: an environment light is an error; light: a sky_sphere that brdf "
                    "finishes importance-sample (povray-facet's brdf_sky_sampling); "
                    "background: export it as the "
                    "background only (it then lights no surface: an approximation)")
        ->check(CLI::IsMember({"error", "background", "light"}))
        ->capture_default_str();
    cmd->add_option("--media-intervals", o->pov.media_intervals,
                    "media: POV-Ray intervals per medium along a ray (two samples each; exact "
                    "for absorption, a quadrature of the lit scattering)")
        ->check(CLI::Range(1, 200))
        ->capture_default_str();
    cmd->add_option("--sky-samples", o->pov.sky_samples,
                    "with --environment light: sky samples per camera-ray hit "
                    "(brdf_sky_sampling N; 1 at deeper hits)")
        ->check(CLI::Range(1, 4096))
        ->capture_default_str();
    cmd->add_option("--radiosity", o->pov.radiosity,
                    "POV-Ray radiosity for the indirect light (approximates `--integrator path`): "
                    "off, low (50,1.0,4), medium (200,0.4,8), high (800,0.15,16) or "
                    "COUNT,ERROR_BOUND,RECURSION_LIMIT")
        ->capture_default_str();
    cmd->add_option("--mipmap", o->pov.mipmap,
                    "image textures with the mipmap filter (the default): error, or linear: "
                    "POV-Ray's bilinear lookup of the full image (exact where the texture is "
                    "magnified, sharper where it is minified)")
        ->check(CLI::IsMember({"error", "linear"}))
        ->capture_default_str();
    cmd->callback([o] { run_export_pov(*o); });
}

}  // namespace facet::cli
